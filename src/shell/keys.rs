//! Key names: the names the settings file uses for keyboard keys, which are winit's physical key codes.
//!
//! Why a table: the bindings (in `input`, which knows nothing of winit) must tell a typo (`"ArowUp"`) from
//! a key, and winit offers no list of its key codes. Every name below is checked against winit at compile
//! time (each is written as `KeyCode::NAME`), and a test checks that each is the name the game gives that
//! key when it is pressed (its `Debug` form), so a binding made in Settings always reads back as a key.

use winit::keyboard::KeyCode;

macro_rules! key_codes {
    ($($name:ident),* $(,)?) => {
        /// Every key code of winit 0.30 with its name, in winit's order.
        pub const KEYS: &[(KeyCode, &str)] = &[$((KeyCode::$name, stringify!($name))),*];
    };
}

key_codes![
    Backquote,
    Backslash,
    BracketLeft,
    BracketRight,
    Comma,
    Digit0,
    Digit1,
    Digit2,
    Digit3,
    Digit4,
    Digit5,
    Digit6,
    Digit7,
    Digit8,
    Digit9,
    Equal,
    IntlBackslash,
    IntlRo,
    IntlYen,
    KeyA,
    KeyB,
    KeyC,
    KeyD,
    KeyE,
    KeyF,
    KeyG,
    KeyH,
    KeyI,
    KeyJ,
    KeyK,
    KeyL,
    KeyM,
    KeyN,
    KeyO,
    KeyP,
    KeyQ,
    KeyR,
    KeyS,
    KeyT,
    KeyU,
    KeyV,
    KeyW,
    KeyX,
    KeyY,
    KeyZ,
    Minus,
    Period,
    Quote,
    Semicolon,
    Slash,
    AltLeft,
    AltRight,
    Backspace,
    CapsLock,
    ContextMenu,
    ControlLeft,
    ControlRight,
    Enter,
    SuperLeft,
    SuperRight,
    ShiftLeft,
    ShiftRight,
    Space,
    Tab,
    Convert,
    KanaMode,
    Lang1,
    Lang2,
    Lang3,
    Lang4,
    Lang5,
    NonConvert,
    Delete,
    End,
    Help,
    Home,
    Insert,
    PageDown,
    PageUp,
    ArrowDown,
    ArrowLeft,
    ArrowRight,
    ArrowUp,
    NumLock,
    Numpad0,
    Numpad1,
    Numpad2,
    Numpad3,
    Numpad4,
    Numpad5,
    Numpad6,
    Numpad7,
    Numpad8,
    Numpad9,
    NumpadAdd,
    NumpadBackspace,
    NumpadClear,
    NumpadClearEntry,
    NumpadComma,
    NumpadDecimal,
    NumpadDivide,
    NumpadEnter,
    NumpadEqual,
    NumpadHash,
    NumpadMemoryAdd,
    NumpadMemoryClear,
    NumpadMemoryRecall,
    NumpadMemoryStore,
    NumpadMemorySubtract,
    NumpadMultiply,
    NumpadParenLeft,
    NumpadParenRight,
    NumpadStar,
    NumpadSubtract,
    Escape,
    Fn,
    FnLock,
    PrintScreen,
    ScrollLock,
    Pause,
    BrowserBack,
    BrowserFavorites,
    BrowserForward,
    BrowserHome,
    BrowserRefresh,
    BrowserSearch,
    BrowserStop,
    Eject,
    LaunchApp1,
    LaunchApp2,
    LaunchMail,
    MediaPlayPause,
    MediaSelect,
    MediaStop,
    MediaTrackNext,
    MediaTrackPrevious,
    Power,
    Sleep,
    AudioVolumeDown,
    AudioVolumeMute,
    AudioVolumeUp,
    WakeUp,
    Meta,
    Hyper,
    Turbo,
    Abort,
    Resume,
    Suspend,
    Again,
    Copy,
    Cut,
    Find,
    Open,
    Paste,
    Props,
    Select,
    Undo,
    Hiragana,
    Katakana,
    F1,
    F2,
    F3,
    F4,
    F5,
    F6,
    F7,
    F8,
    F9,
    F10,
    F11,
    F12,
    F13,
    F14,
    F15,
    F16,
    F17,
    F18,
    F19,
    F20,
    F21,
    F22,
    F23,
    F24,
    F25,
    F26,
    F27,
    F28,
    F29,
    F30,
    F31,
    F32,
    F33,
    F34,
    F35
];

/// The name a key is bound by (as the settings file writes it).
#[must_use]
pub fn key_name(code: KeyCode) -> String {
    format!("{code:?}")
}

/// A key as keyboards label it (`KeyC` is `C`, `ArrowLeft` is `Left`, `Numpad0` is `Num 0`).
///
/// For menus, Settings and the HUD; the settings file keeps winit's names, which follow a key's place on
/// any layout. A name this table does not know is shown with spaces between its words (`AudioVolumeUp` is
/// `Audio Volume Up`).
#[must_use]
pub fn key_label(name: &str) -> String {
    if let Some(letter) = name.strip_prefix("Key").filter(|l| l.len() == 1) {
        return letter.to_string();
    }
    if let Some(digit) = name.strip_prefix("Digit").filter(|d| d.len() == 1) {
        return digit.to_string();
    }
    if let Some(rest) = name.strip_prefix("Numpad") {
        let key = match rest {
            "Add" => "+",
            "Subtract" => "-",
            "Multiply" => "*",
            "Divide" => "/",
            "Decimal" => ".",
            "Equal" => "=",
            "Comma" => ",",
            other => return format!("Num {}", words(other)),
        };
        return format!("Num {key}");
    }
    for (side, word) in [("Left", "Left"), ("Right", "Right")] {
        for (prefix, key) in [("Shift", "Shift"), ("Control", "Ctrl"), ("Alt", "Alt"), ("Super", "Super")] {
            if name.strip_prefix(prefix) == Some(side) {
                return format!("{word} {key}");
            }
        }
    }
    let label = match name {
        "ArrowUp" => "Up",
        "ArrowDown" => "Down",
        "ArrowLeft" => "Left",
        "ArrowRight" => "Right",
        "Escape" => "Esc",
        "Backquote" => "`",
        "Minus" => "-",
        "Equal" => "=",
        "BracketLeft" => "[",
        "BracketRight" => "]",
        "Backslash" => "\\",
        "IntlBackslash" => "\\ (left of Z)",
        "Semicolon" => ";",
        "Quote" => "'",
        "Comma" => ",",
        "Period" => ".",
        "Slash" => "/",
        "ContextMenu" => "Menu",
        other => return words(other),
    };
    label.to_string()
}

/// `CamelCase` as separate words (`PageUp` is `Page Up`, `F11` stays `F11`).
fn words(name: &str) -> String {
    let mut out = String::with_capacity(name.len() + 4);
    let mut previous_lower = false;
    for c in name.chars() {
        if c.is_ascii_uppercase() && previous_lower {
            out.push(' ');
        }
        previous_lower = c.is_ascii_lowercase();
        out.push(c);
    }
    out
}

/// Keys as keyboards label them, joined by `separator`.
#[must_use]
pub fn key_labels(names: &[String], separator: &str) -> String {
    names.iter().map(|n| key_label(n)).collect::<Vec<_>>().join(separator)
}

/// Whether `name` names a key.
#[must_use]
pub fn is_key_name(name: &str) -> bool {
    KEYS.iter().any(|(_, n)| *n == name)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_name_is_the_name_a_pressed_key_gets() {
        for (code, name) in KEYS {
            assert_eq!(key_name(*code), *name);
        }
        assert!(KEYS.len() >= 190, "{} keys", KEYS.len());
        assert!(is_key_name("ArrowUp") && is_key_name("KeyW") && is_key_name("F35"));
        assert!(!is_key_name("ArowUp") && !is_key_name("arrowup") && !is_key_name(""));
    }

    #[test]
    fn keys_are_shown_as_keyboards_label_them() {
        for (name, label) in [
            ("KeyC", "C"),
            ("Digit7", "7"),
            ("ArrowLeft", "Left"),
            ("Space", "Space"),
            ("Numpad0", "Num 0"),
            ("NumpadAdd", "Num +"),
            ("NumpadEnter", "Num Enter"),
            ("ShiftLeft", "Left Shift"),
            ("ControlRight", "Right Ctrl"),
            ("Escape", "Esc"),
            ("PageUp", "Page Up"),
            ("CapsLock", "Caps Lock"),
            ("Backquote", "`"),
            ("F11", "F11"),
            ("AudioVolumeUp", "Audio Volume Up"),
        ] {
            assert_eq!(key_label(name), label, "{name}");
        }
        // Every key has a label of its own: no two keys look alike in a menu.
        let mut labels: Vec<String> = KEYS.iter().map(|(_, n)| key_label(n)).collect();
        labels.sort();
        let before = labels.len();
        labels.dedup();
        assert_eq!(labels.len(), before, "two keys share a label");
        assert_eq!(key_labels(&["KeyW".into(), "ArrowUp".into()], "/"), "W/Up");
    }
}
