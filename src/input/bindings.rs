//! Key bindings: which keyboard keys drive which action, rebindable and saved in the settings file.
//!
//! Keys are named as winit names its physical key codes (`"ArrowUp"`, `"KeyW"`, `"Space"`), so the file is
//! readable and independent of keyboard layout (a binding follows the key's place, as games expect).
//! This module knows nothing of winit: the shell turns a key code into its name.

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};
use thiserror::Error;

/// Something a key can do in the race.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Action {
    /// Steer left (eased in and out, so a tap is a correction).
    SteerLeft,
    /// Steer right.
    SteerRight,
    /// Full throttle while held.
    Throttle,
    /// Full brake while held.
    Brake,
    /// The next camera view.
    ChangeView,
    /// Pause or resume.
    Pause,
    /// Mute or unmute the sound (saved in the settings like the volumes).
    Mute,
}

impl Action {
    /// Every action, in the order the settings list them.
    pub const ALL: [Action; 7] = [
        Action::SteerLeft,
        Action::SteerRight,
        Action::Throttle,
        Action::Brake,
        Action::ChangeView,
        Action::Pause,
        Action::Mute,
    ];

    /// A short label for menus.
    #[must_use]
    pub fn label(self) -> &'static str {
        match self {
            Action::SteerLeft => "steer left",
            Action::SteerRight => "steer right",
            Action::Throttle => "throttle",
            Action::Brake => "brake",
            Action::ChangeView => "change view",
            Action::Pause => "pause",
            Action::Mute => "mute sound",
        }
    }
}

/// Keys kept for the program itself: menus, window and debugging; they cannot be bound to an action.
pub const RESERVED: [&str; 12] =
    ["Escape", "Enter", "F3", "F11", "Minus", "Equal", "Digit1", "Digit2", "Digit3", "Digit4", "Digit5", "Tab"];

/// The keys bound to each action (at most [`Bindings::MAX_KEYS`] each; a key drives one action at most).
/// In the file, an object from action to key names: `{"throttle": ["ArrowUp", "KeyW"], ...}`.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(transparent)]
pub struct Bindings {
    /// Key names per action (an ordered map: the file lists actions in a fixed order).
    keys: BTreeMap<Action, Vec<String>>,
}

impl Default for Bindings {
    fn default() -> Self {
        let k = |names: &[&str]| names.iter().map(|s| (*s).to_string()).collect::<Vec<_>>();
        Self {
            keys: BTreeMap::from([
                (Action::SteerLeft, k(&["ArrowLeft", "KeyA"])),
                (Action::SteerRight, k(&["ArrowRight", "KeyD"])),
                (Action::Throttle, k(&["ArrowUp", "KeyW"])),
                (Action::Brake, k(&["ArrowDown", "KeyS"])),
                (Action::ChangeView, k(&["KeyC"])),
                (Action::Pause, k(&["KeyP"])),
                (Action::Mute, k(&["KeyM"])),
            ]),
        }
    }
}

impl Bindings {
    /// Most keys one action may have.
    pub const MAX_KEYS: usize = 4;

    /// The action `key` drives, if any.
    #[must_use]
    pub fn action(&self, key: &str) -> Option<Action> {
        self.keys.iter().find(|(_, ks)| ks.iter().any(|k| k == key)).map(|(a, _)| *a)
    }

    /// The keys bound to `action`.
    #[must_use]
    pub fn keys(&self, action: Action) -> &[String] {
        self.keys.get(&action).map_or(&[], Vec::as_slice)
    }

    /// Binds `key` to `action` alone (replacing its keys) and unbinds it from any other action; refuses a
    /// reserved key, naming it.
    pub fn bind(&mut self, action: Action, key: &str) -> Result<(), BindError> {
        if RESERVED.contains(&key) {
            return Err(BindError::Reserved { key: key.to_string() });
        }
        for ks in self.keys.values_mut() {
            ks.retain(|k| k != key);
        }
        self.keys.insert(action, vec![key.to_string()]);
        Ok(())
    }

    /// Bindings read from a settings file made whole, and what was repaired, one line each naming the key
    /// and the action. Reserved keys, names that `is_key` does not know (a typo such as `"ArowUp"`),
    /// duplicates (the first action in [`Action::ALL`] order keeps a key) and keys past
    /// [`Bindings::MAX_KEYS`] are dropped. An action left with no key (or not in the file) gets those of
    /// its default keys that no other action has; when every one of them is bound to another action (which
    /// keeps it: the file asked for that), it gets the first free key of [`SPARE_KEYS`]. The note says
    /// which default is taken by which action and which key is used; an action missing from the file that
    /// gets all its default keys needs no note.
    #[must_use]
    pub fn repaired(&self, is_key: impl Fn(&str) -> bool) -> (Bindings, Vec<String>) {
        let mut notes = vec![];
        let mut out = BTreeMap::new();
        for action in Action::ALL {
            let mut ks: Vec<String> = vec![];
            for key in self.keys(action) {
                let why = if RESERVED.contains(&key.as_str()) {
                    Some("is reserved for menus and the window".to_string())
                } else if !is_key(key) {
                    Some("is not a key name (names are like ArrowUp, KeyW, Space, Digit7)".to_string())
                } else if let Some(other) =
                    out.iter().find_map(|(a, v): (&Action, &Vec<String>)| v.contains(key).then_some(*a))
                {
                    Some(format!("is already bound to {}", other.label()))
                } else if ks.contains(key) {
                    Some("is listed twice".to_string())
                } else if ks.len() >= Self::MAX_KEYS {
                    Some(format!("is past the {} keys an action may have", Self::MAX_KEYS))
                } else {
                    None
                };
                match why {
                    Some(why) => notes.push(format!("key {key:?} for {} {why}: dropped", action.label())),
                    None => ks.push(key.clone()),
                }
            }
            out.insert(action, ks);
        }
        let defaults = Bindings::default();
        for action in Action::ALL {
            if out.get(&action).is_some_and(|ks| !ks.is_empty()) {
                continue;
            }
            let holder = |key: &str| out.iter().find_map(|(a, v)| v.iter().any(|k| k == key).then_some(*a));
            let (mut free, mut taken) = (vec![], vec![]);
            for k in defaults.keys(action) {
                match holder(k) {
                    None => free.push(k.clone()),
                    Some(other) => taken.push(format!("{k} is bound to {}", other.label())),
                }
            }
            let listed = self.keys.contains_key(&action);
            let mut note = format!("{} {}", action.label(), if listed { "had no key" } else { "is not in the file" });
            if !taken.is_empty() {
                note += &format!(" and its default {}", taken.join(", "));
            }
            let keys = if free.is_empty() {
                let spare: Vec<String> =
                    SPARE_KEYS.iter().find(|k| holder(k).is_none()).map(|k| (*k).to_string()).into_iter().collect();
                note +=
                    &spare.first().map_or_else(|| ": no free key is left".into(), |k| format!(": {k} used instead"));
                spare
            } else {
                note += &format!(": default {} used", free.join(", "));
                free
            };
            if listed || !taken.is_empty() {
                notes.push(note);
            }
            out.insert(action, keys);
        }
        (Bindings { keys: out }, notes)
    }
}

/// Keys given, in this order, to an action left with no key whose default keys are bound to other actions
/// (none of them a default key: M, which mutes, is not among them).
pub const SPARE_KEYS: [&str; 15] = [
    "KeyJ", "KeyL", "KeyI", "KeyK", "KeyU", "KeyO", "KeyH", "KeyG", "KeyB", "KeyN", "KeyV", "KeyF", "KeyE", "KeyQ",
    "KeyZ",
];

/// Why a key could not be bound.
#[derive(Debug, Error, PartialEq, Eq)]
pub enum BindError {
    /// The key is kept for menus and the window.
    #[error("{key} is reserved for menus and the window")]
    Reserved {
        /// The key's name.
        key: String,
    },
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Key names for these tests: letters, arrows and a few others (the shell checks against winit's list).
    fn known(k: &str) -> bool {
        (k.len() == 4 && k.starts_with("Key")) || k.starts_with("Arrow") || ["Space", "Escape"].contains(&k)
    }

    #[test]
    fn defaults_cover_every_action_with_distinct_keys() {
        let b = Bindings::default();
        for a in Action::ALL {
            assert!(!b.keys(a).is_empty(), "{a:?}");
            for k in b.keys(a) {
                assert_eq!(b.action(k), Some(a));
            }
        }
        assert_eq!(b.repaired(known), (b.clone(), vec![]));
        assert_eq!(b.keys(Action::Mute), ["KeyM"]);
        for k in SPARE_KEYS {
            assert_eq!(b.action(k), None, "spare key {k} is no default key");
        }
    }

    #[test]
    fn binding_a_key_moves_it_and_refuses_reserved_keys() {
        let mut b = Bindings::default();
        b.bind(Action::Throttle, "KeyA").unwrap();
        assert_eq!(b.keys(Action::Throttle), ["KeyA"]);
        assert_eq!(b.keys(Action::SteerLeft), ["ArrowLeft"]);
        assert_eq!(b.action("KeyA"), Some(Action::Throttle));
        assert_eq!(b.action("ArrowUp"), None);
        assert_eq!(b.bind(Action::Brake, "Escape"), Err(BindError::Reserved { key: "Escape".into() }));
        assert_eq!(b.keys(Action::Brake), ["ArrowDown", "KeyS"]);
    }

    fn repair(json: &str) -> (Bindings, Vec<String>) {
        serde_json::from_str::<Bindings>(json).unwrap().repaired(known)
    }

    #[test]
    fn a_hand_edited_file_is_repaired() {
        let (r, notes) = repair(r#"{"throttle":["KeyA","Escape","","KeyT"],"steer_left":["KeyQ","KeyA"]}"#);
        // Steering left comes first in the order: it keeps KeyA.
        assert_eq!(r.keys(Action::SteerLeft), ["KeyQ", "KeyA"]);
        assert_eq!(r.keys(Action::Throttle), ["KeyT"]);
        assert_eq!(r.keys(Action::Brake), ["ArrowDown", "KeyS"]);
        assert_eq!(r.keys(Action::SteerRight), ["ArrowRight", "KeyD"]);
        assert!(notes.contains(&r#"key "Escape" for throttle is reserved for menus and the window: dropped"#.into()));
        assert!(notes.contains(&r#"key "KeyA" for throttle is already bound to steer left: dropped"#.into()));
        assert_eq!(r.repaired(known).1, Vec::<String>::new());
        assert!(serde_json::from_str::<Bindings>(r#"{"fly":["KeyF"]}"#).is_err());
    }

    #[test]
    fn a_typo_is_named_with_its_action_and_the_default_used_is_said() {
        let (r, notes) = repair(r#"{"throttle":["ArowUp"],"brake":["KeyS","Spcae"]}"#);
        assert_eq!(r.keys(Action::Throttle), ["ArrowUp", "KeyW"]);
        assert_eq!(r.keys(Action::Brake), ["KeyS"]);
        assert_eq!(
            notes,
            [
                r#"key "ArowUp" for throttle is not a key name (names are like ArrowUp, KeyW, Space, Digit7): dropped"#,
                r#"key "Spcae" for brake is not a key name (names are like ArrowUp, KeyW, Space, Digit7): dropped"#,
                "throttle had no key: default ArrowUp, KeyW used",
            ]
        );
    }

    #[test]
    fn an_action_whose_default_keys_are_taken_gets_a_free_key_and_the_note_says_so() {
        // The default steering keys given to throttle and brake: steering must still be possible.
        let (r, notes) = repair(r#"{"throttle":["ArrowLeft","KeyA"],"brake":["ArrowRight"],"steer_left":[]}"#);
        assert_eq!(r.keys(Action::Throttle), ["ArrowLeft", "KeyA"]);
        assert_eq!(r.keys(Action::SteerLeft), ["KeyJ"]);
        assert_eq!(r.keys(Action::SteerRight), ["KeyD"]);
        assert_eq!(
            notes,
            [
                "steer left had no key and its default ArrowLeft is bound to throttle, KeyA is bound to throttle: \
                 KeyJ used instead",
                "steer right is not in the file and its default ArrowRight is bound to brake: default KeyD used",
            ]
        );
        for a in Action::ALL {
            assert!(!r.keys(a).is_empty(), "{a:?} has a key");
            assert!(r.keys(a).iter().all(|k| r.action(k) == Some(a)), "{a:?}'s keys drive it alone");
        }
        // A spare key already bound is skipped; a single-key default taken gets the next free spare.
        let (r, notes) = repair(r#"{"steer_left":["KeyJ"],"pause":["KeyC"]}"#);
        assert_eq!(r.keys(Action::ChangeView), ["KeyL"]);
        assert_eq!(notes, ["change view is not in the file and its default KeyC is bound to pause: KeyL used instead"]);
    }
}
