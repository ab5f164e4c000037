//! Key bindings: which keyboard keys drive which action, rebindable and saved in the settings file.
//!
//! Keys are named as winit names its physical key codes (`"ArrowUp"`, `"KeyW"`, `"Space"`), so the file is
//! readable and independent of keyboard layout (a binding follows the key's place, as games expect).
//! This module knows nothing of winit: the shell turns a key code into its name.

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

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
}

impl Action {
    /// Every action, in the order the settings list them.
    pub const ALL: [Action; 6] =
        [Action::SteerLeft, Action::SteerRight, Action::Throttle, Action::Brake, Action::ChangeView, Action::Pause];

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
    pub fn bind(&mut self, action: Action, key: &str) -> Result<(), String> {
        if RESERVED.contains(&key) {
            return Err(format!("{key} is reserved for menus and the window"));
        }
        for ks in self.keys.values_mut() {
            ks.retain(|k| k != key);
        }
        self.keys.insert(action, vec![key.to_string()]);
        Ok(())
    }

    /// Bindings read from a settings file made whole: every action present; reserved, duplicate (the first
    /// action in [`Action::ALL`] order keeps a key), overlong and empty names dropped; an action left with no key gets its default keys back where they
    /// are free. Returns what was repaired, one line each.
    #[must_use]
    pub fn repaired(&self) -> (Bindings, Vec<String>) {
        let mut notes = vec![];
        let mut seen: Vec<String> = vec![];
        let mut out = BTreeMap::new();
        for action in Action::ALL {
            let mut ks = vec![];
            for key in self.keys(action) {
                let bad = key.is_empty() || key.len() > 32 || RESERVED.contains(&key.as_str());
                if bad || seen.contains(key) || ks.len() >= Self::MAX_KEYS {
                    notes.push(format!("key {key:?} for {} dropped", action.label()));
                    continue;
                }
                seen.push(key.clone());
                ks.push(key.clone());
            }
            out.insert(action, ks);
        }
        let defaults = Bindings::default();
        for (action, ks) in &mut out {
            if ks.is_empty() {
                ks.extend(defaults.keys(*action).iter().filter(|k| !seen.contains(k)).cloned());
                seen.extend(ks.iter().cloned());
                notes.push(format!("{} had no key: default restored", action.label()));
            }
        }
        (Bindings { keys: out }, notes)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_cover_every_action_with_distinct_keys() {
        let b = Bindings::default();
        for a in Action::ALL {
            assert!(!b.keys(a).is_empty(), "{a:?}");
            for k in b.keys(a) {
                assert_eq!(b.action(k), Some(a));
            }
        }
        assert_eq!(b.repaired(), (b.clone(), vec![]));
    }

    #[test]
    fn binding_a_key_moves_it_and_refuses_reserved_keys() {
        let mut b = Bindings::default();
        b.bind(Action::Throttle, "KeyA").unwrap();
        assert_eq!(b.keys(Action::Throttle), ["KeyA"]);
        assert_eq!(b.keys(Action::SteerLeft), ["ArrowLeft"]);
        assert_eq!(b.action("KeyA"), Some(Action::Throttle));
        assert_eq!(b.action("ArrowUp"), None);
        assert!(b.bind(Action::Brake, "Escape").unwrap_err().contains("Escape"));
        assert_eq!(b.keys(Action::Brake), ["ArrowDown", "KeyS"]);
    }

    #[test]
    fn a_hand_edited_file_is_repaired() {
        let json = r#"{"throttle":["KeyA","Escape","","KeyT"],"steer_left":["KeyQ","KeyA"]}"#;
        let b: Bindings = serde_json::from_str(json).unwrap();
        let (r, notes) = b.repaired();
        // Steering left comes first in the order: it keeps KeyA.
        assert_eq!(r.keys(Action::SteerLeft), ["KeyQ", "KeyA"]);
        assert_eq!(r.keys(Action::Throttle), ["KeyT"]);
        assert_eq!(r.keys(Action::Brake), ["ArrowDown", "KeyS"]);
        assert_eq!(r.keys(Action::SteerRight), ["ArrowRight", "KeyD"]);
        assert!(notes.iter().any(|n| n.contains("Escape")), "{notes:?}");
        assert_eq!(r.repaired().1, Vec::<String>::new());
        // Defaults come back only where free.
        let (r, _) = serde_json::from_str::<Bindings>(r#"{"pause":["KeyC"]}"#).unwrap().repaired();
        assert_eq!((r.keys(Action::Pause), r.keys(Action::ChangeView)), (&["KeyC".to_string()][..], &[][..]));
        assert!(serde_json::from_str::<Bindings>(r#"{"fly":["KeyF"]}"#).is_err());
    }
}
