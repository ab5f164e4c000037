//! Gamepad buttons by the pad's own names: the button at the bottom of the face is `A` on an Xbox pad,
//! `Cross` on a PlayStation pad and `B` on a Nintendo one; the pause button is `Menu`, `Options` or `+`.
//!
//! Why: gilrs names buttons by their place (`South`, `Start`), which no pad prints on its buttons. The
//! maker is told by the USB vendor id the pad reports (Sony 0x054c, Nintendo 0x057e); any other pad is
//! labelled as the Xbox layout most PC pads copy.

/// How a pad's maker labels its buttons.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum PadStyle {
    /// Xbox and the many pads that copy it (A, B, X, Y; Menu, View).
    #[default]
    Xbox,
    /// PlayStation (Cross, Circle, Square, Triangle; Options, Share).
    PlayStation,
    /// Nintendo (B, A, Y, X at the Xbox's A, B, X, Y places; +, -).
    Nintendo,
}

/// A button by its place on the pad, as the game uses them.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PadPlace {
    /// The bottom face button (confirms in menus).
    South,
    /// The right face button (goes back).
    East,
    /// The top face button (changes the view).
    North,
    /// The left face button.
    West,
    /// The start button, right of the centre (pauses).
    Start,
    /// The select button, left of the centre.
    Select,
}

impl PadStyle {
    /// The style of a pad with USB vendor id `vendor` (`None` when the pad reports none).
    #[must_use]
    pub fn of_vendor(vendor: Option<u16>) -> Self {
        match vendor {
            Some(0x054c) => PadStyle::PlayStation,
            Some(0x057e) => PadStyle::Nintendo,
            _ => PadStyle::Xbox,
        }
    }

    /// The name printed on the button at `place`.
    #[must_use]
    pub fn button(self, place: PadPlace) -> &'static str {
        use PadPlace as P;
        match (self, place) {
            (PadStyle::Xbox, P::South) | (PadStyle::Nintendo, P::East) => "A",
            (PadStyle::Xbox, P::East) | (PadStyle::Nintendo, P::South) => "B",
            (PadStyle::Xbox, P::West) | (PadStyle::Nintendo, P::North) => "X",
            (PadStyle::Xbox, P::North) | (PadStyle::Nintendo, P::West) => "Y",
            (PadStyle::Xbox, P::Start) => "Menu",
            (PadStyle::Xbox, P::Select) => "View",
            (PadStyle::PlayStation, P::South) => "Cross",
            (PadStyle::PlayStation, P::East) => "Circle",
            (PadStyle::PlayStation, P::West) => "Square",
            (PadStyle::PlayStation, P::North) => "Triangle",
            (PadStyle::PlayStation, P::Start) => "Options",
            (PadStyle::PlayStation, P::Select) => "Share",
            (PadStyle::Nintendo, P::Start) => "+",
            (PadStyle::Nintendo, P::Select) => "-",
        }
    }

    /// The menus' one line on the pad: what steers and drives, and the buttons by this pad's names.
    #[must_use]
    pub fn help(self) -> String {
        format!(
            "Gamepad: stick steers, right trigger accelerates, left trigger brakes; D-pad and {} in menus; {} \
             pauses ({} resumes); {} changes the view.",
            self.button(PadPlace::South),
            self.button(PadPlace::Start),
            self.button(PadPlace::East),
            self.button(PadPlace::North)
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_maker_s_buttons_by_their_printed_names() {
        assert_eq!(PadStyle::of_vendor(Some(0x054c)), PadStyle::PlayStation);
        assert_eq!(PadStyle::of_vendor(Some(0x057e)), PadStyle::Nintendo);
        assert_eq!(PadStyle::of_vendor(Some(0x045e)), PadStyle::Xbox);
        assert_eq!(PadStyle::of_vendor(None), PadStyle::Xbox);
        let places = [PadPlace::South, PadPlace::East, PadPlace::West, PadPlace::North, PadPlace::Start];
        assert_eq!(places.map(|p| PadStyle::Xbox.button(p)), ["A", "B", "X", "Y", "Menu"]);
        assert_eq!(
            places.map(|p| PadStyle::PlayStation.button(p)),
            ["Cross", "Circle", "Square", "Triangle", "Options"]
        );
        assert_eq!(places.map(|p| PadStyle::Nintendo.button(p)), ["B", "A", "Y", "X", "+"]);
        assert!(PadStyle::PlayStation.help().contains("Cross in menus; Options pauses (Circle resumes); Triangle"));
    }
}
