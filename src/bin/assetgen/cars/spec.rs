//! The cars' specification: the eight designs (proportions and livery), the wheel and ride dimensions every
//! design shares, and the layout of the atlas and the detail texture.
//!
//! The models are built to these numbers and the textures painted to them, so both `models` and `paint` read
//! them; they live in a file of their own, which imports nothing from `cars`, so that neither reaches back
//! into `cars/mod.rs`: the parent ties the children together, nothing flows back up.

use crate::paint::Rgba;

/// How the livery's second colour is laid out.
#[derive(Clone, Copy, Debug)]
pub(super) enum Pattern {
    Stripe,
    TwoTone,
    Chevron,
    Band,
}

/// One car design: proportions and livery.
#[derive(Clone, Copy, Debug)]
pub(super) struct Design {
    /// Race number, on the doors and the roof (the number plate shows a number made from it).
    pub(super) number: u32,
    /// Overall length and width, in metres.
    pub(super) length: f32,
    pub(super) width: f32,
    /// Height of the body's top (the cabin rises above it).
    pub(super) body_height: f32,
    /// Height of the cabin's roof.
    pub(super) cabin_height: f32,
    /// Cabin start and end along the length (0 = nose, 1 = tail).
    pub(super) cabin: (f32, f32),
    /// Nose height as a fraction of the body height.
    pub(super) nose: f32,
    /// Whether the close model carries a rear wing.
    pub(super) wing: bool,
    /// The livery's main colour.
    pub(super) base: Rgba,
    /// The livery's second colour, laid out by `pattern`.
    pub(super) accent: Rgba,
    pub(super) pattern: Pattern,
}

/// The eight designs, in file order (`car_1` is the first).
pub(super) const DESIGNS: [Design; 8] = [
    Design {
        number: 1,
        length: 4.5,
        width: 1.9,
        body_height: 0.75,
        cabin_height: 1.15,
        cabin: (0.38, 0.72),
        nose: 0.55,
        wing: true,
        base: [200, 30, 30, 255],
        accent: [250, 250, 250, 255],
        pattern: Pattern::Stripe,
    },
    Design {
        number: 2,
        length: 4.7,
        width: 1.95,
        body_height: 0.7,
        cabin_height: 1.1,
        cabin: (0.42, 0.75),
        nose: 0.5,
        wing: true,
        base: [20, 60, 170, 255],
        accent: [250, 200, 20, 255],
        pattern: Pattern::TwoTone,
    },
    Design {
        number: 3,
        length: 4.3,
        width: 1.85,
        body_height: 0.8,
        cabin_height: 1.25,
        cabin: (0.35, 0.8),
        nose: 0.65,
        wing: false,
        base: [30, 140, 60, 255],
        accent: [240, 240, 240, 255],
        pattern: Pattern::Band,
    },
    Design {
        number: 5,
        length: 4.6,
        width: 1.9,
        body_height: 0.72,
        cabin_height: 1.12,
        cabin: (0.4, 0.7),
        nose: 0.5,
        wing: true,
        base: [250, 200, 20, 255],
        accent: [20, 20, 20, 255],
        pattern: Pattern::Chevron,
    },
    Design {
        number: 7,
        length: 4.4,
        width: 1.8,
        body_height: 0.78,
        cabin_height: 1.2,
        cabin: (0.36, 0.76),
        nose: 0.6,
        wing: false,
        base: [240, 240, 240, 255],
        accent: [30, 90, 200, 255],
        pattern: Pattern::Stripe,
    },
    Design {
        number: 8,
        length: 4.8,
        width: 2.0,
        body_height: 0.68,
        cabin_height: 1.05,
        cabin: (0.45, 0.74),
        nose: 0.45,
        wing: true,
        base: [240, 110, 20, 255],
        accent: [40, 40, 120, 255],
        pattern: Pattern::TwoTone,
    },
    Design {
        number: 11,
        length: 4.5,
        width: 1.88,
        body_height: 0.74,
        cabin_height: 1.16,
        cabin: (0.4, 0.73),
        nose: 0.55,
        wing: true,
        base: [120, 30, 160, 255],
        accent: [240, 240, 240, 255],
        pattern: Pattern::Band,
    },
    Design {
        number: 27,
        length: 4.35,
        width: 1.86,
        body_height: 0.82,
        cabin_height: 1.28,
        cabin: (0.34, 0.78),
        nose: 0.62,
        wing: false,
        base: [25, 25, 25, 255],
        accent: [220, 30, 30, 255],
        pattern: Pattern::Chevron,
    },
];

// Atlas layout (fractions of the 256x256 atlas; the 64 and 16 versions share it). Each region is
// [u0, v0, u1, v1].

/// The body's and cabin's sides (the livery, windows, sill and wheel arches), nose on the left.
pub(super) const SIDE: [f32; 4] = [0.0, 0.0, 1.0, 0.375];
/// The bonnet, roof and boot seen from above: racing stripes, windscreen and rear window.
pub(super) const TOP: [f32; 4] = [0.0, 0.375, 1.0, 0.6875];
/// The nose: grille, lamp areas and windscreen.
pub(super) const FRONT: [f32; 4] = [0.0, 0.6875, 0.25, 1.0];
/// The tail: tail-light bar and rear window.
pub(super) const BACK: [f32; 4] = [0.25, 0.6875, 0.5, 1.0];
/// A wheel's face: tyre and hub.
pub(super) const WHEEL: [f32; 4] = [0.5, 0.6875, 0.75, 1.0];
/// The underside, also the wheels' tread.
pub(super) const UNDER: [f32; 4] = [0.75, 0.6875, 1.0, 1.0];

// Detail texture layout (fractions of the 128x128 detail texture), for the close model's separate polygons.

/// The number plate.
pub(super) const PLATE: [f32; 4] = [0.0, 0.0, 1.0, 0.25];
/// The race-number roundel.
pub(super) const ROUNDEL: [f32; 4] = [0.0, 0.25, 0.5, 0.75];
/// A headlamp.
pub(super) const HEADLAMP: [f32; 4] = [0.5, 0.25, 1.0, 0.5];
/// A tail lamp.
pub(super) const TAIL_LAMP: [f32; 4] = [0.5, 0.5, 1.0, 0.75];

/// Wheel radius, in metres (the axles stand this high above the ground).
pub(super) const WHEEL_RADIUS: f32 = 0.33;
/// Wheel width, in metres.
pub(super) const WHEEL_WIDTH: f32 = 0.26;
/// Ride height: the body's underside above the ground, in metres.
pub(super) const RIDE: f32 = 0.14;
