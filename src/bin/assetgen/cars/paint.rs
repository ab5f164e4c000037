//! The cars' textures: the 256x256 livery atlas (box-filtered to 64 and 16 for the coarser models) and the
//! 128x128 detail texture.

use super::models::{axle_z, body_profile};
use super::spec::{
    BACK, Design, FRONT, HEADLAMP, PLATE, Pattern, RIDE, ROUNDEL, SIDE, TAIL_LAMP, TOP, UNDER, WHEEL, WHEEL_RADIUS,
};
use crate::paint::{Canvas, Rgba};

fn shade(c: Rgba, f: f32) -> Rgba {
    [
        (f32::from(c[0]) * f).min(255.0) as u8,
        (f32::from(c[1]) * f).min(255.0) as u8,
        (f32::from(c[2]) * f).min(255.0) as u8,
        255,
    ]
}

/// Paints the 256x256 atlas: livery on the sides and top, grille and lamps front and back, wheel and tyre.
pub(super) fn paint_atlas(d: &Design) -> Canvas {
    let mut c = Canvas::new(256, 256, d.base);
    let glass = [40, 55, 75, 255];
    let dark = [25, 25, 28, 255];
    let sub = |r: [f32; 4], x0: f32, y0: f32, x1: f32, y1: f32| {
        [r[0] + (r[2] - r[0]) * x0, r[1] + (r[3] - r[1]) * y0, r[0] + (r[2] - r[0]) * x1, r[1] + (r[3] - r[1]) * y1]
    };
    // Side: v = 1 - y / cabin_height; sill dark, livery, windows at cabin height.
    let v_of = |y: f32| 1.0 - y / d.cabin_height;
    match d.pattern {
        Pattern::Stripe => c.rect(sub(SIDE, 0.0, v_of(0.52), 1.0, v_of(0.42)), d.accent),
        Pattern::TwoTone => c.rect(sub(SIDE, 0.0, 0.0, 1.0, v_of(0.5)), d.accent),
        Pattern::Band => c.rect(sub(SIDE, 0.55, 0.0, 0.75, 1.0), d.accent),
        Pattern::Chevron => {
            for k in 0..8 {
                let x = 0.1 + 0.1 * k as f32;
                c.rect(sub(SIDE, x, v_of(0.6 - 0.03 * k as f32), x + 0.05, v_of(0.3 + 0.03 * k as f32)), d.accent);
            }
        }
    }
    c.rect(sub(SIDE, 0.0, v_of(RIDE + 0.1), 1.0, 1.0), shade(d.base, 0.45));
    let (c0, c1) = d.cabin;
    let base = body_profile(d, c0).min(body_profile(d, c1));
    c.rect(sub(SIDE, c0 + 0.03, v_of(d.cabin_height - 0.05), c1 - 0.03, v_of(base + 0.05)), glass);
    for z in axle_z(d) {
        let t = z / d.length + 0.5;
        let cx = SIDE[0] + t * (SIDE[2] - SIDE[0]);
        let cy = SIDE[1] + v_of(WHEEL_RADIUS) * (SIDE[3] - SIDE[1]);
        c.disc(cx, cy, WHEEL_RADIUS / d.length * 1.1, dark);
    }
    // The race number painted on the door too, for the mid and long models (the close one has its own polygon).
    let door_t = 0.5 * (c0 + c1);
    let (rx, ry) = (SIDE[0] + door_t * (SIDE[2] - SIDE[0]), SIDE[1] + v_of(0.42) * (SIDE[3] - SIDE[1]));
    c.disc(rx, ry, 0.05, [250, 250, 250, 255]);
    c.number(d.number, rx, ry, 0.05, [10, 10, 10, 255]);
    // Top: racing stripes, windscreen and roof.
    if !matches!(d.pattern, Pattern::Band) {
        c.rect(sub(TOP, 0.0, 0.4, 1.0, 0.48), d.accent);
        c.rect(sub(TOP, 0.0, 0.52, 1.0, 0.6), d.accent);
    }
    c.rect(sub(TOP, c0, 0.15, c0 + 0.3 * (c1 - c0), 0.85), glass);
    c.rect(sub(TOP, c0 + 0.8 * (c1 - c0), 0.15, c1, 0.85), glass);
    // Front: grille and lamp areas; back: tail-light bar.
    c.rect(sub(FRONT, 0.25, 0.65, 0.75, 0.85), dark);
    c.rect(sub(FRONT, 0.05, 0.45, 0.3, 0.6), [240, 240, 200, 255]);
    c.rect(sub(FRONT, 0.7, 0.45, 0.95, 0.6), [240, 240, 200, 255]);
    c.rect(sub(FRONT, 0.15, 0.0, 0.85, 0.35), glass);
    c.rect(sub(BACK, 0.05, 0.45, 0.95, 0.6), [200, 20, 20, 255]);
    c.rect(sub(BACK, 0.15, 0.0, 0.85, 0.35), glass);
    // Wheel face: tyre with a hub; underside and tread: dark.
    c.rect(WHEEL, dark);
    c.disc(0.5 + 0.125, 0.6875 + 0.15625, 0.07, [170, 170, 175, 255]);
    c.disc(0.5 + 0.125, 0.6875 + 0.15625, 0.025, shade(d.base, 0.8));
    c.rect(UNDER, [35, 35, 38, 255]);
    c
}

/// Paints the 128x128 detail texture: number plate, race-number roundel, head and tail lamps.
pub(super) fn paint_detail(d: &Design) -> Canvas {
    let mut c = Canvas::new(128, 128, [0, 0, 0, 255]);
    c.rect(PLATE, [245, 245, 235, 255]);
    c.rect([0.03, 0.03, 0.97, 0.22], [250, 250, 245, 255]);
    c.number(1000 + d.number * 37 % 1000, 0.5, 0.125, 0.13, [20, 20, 20, 255]);
    c.rect(ROUNDEL, d.base);
    c.disc(0.25, 0.5, 0.22, [250, 250, 250, 255]);
    c.number(d.number, 0.25, 0.5, 0.2, [10, 10, 10, 255]);
    c.rect(HEADLAMP, [60, 60, 60, 255]);
    c.disc(0.75, 0.375, 0.11, [255, 250, 210, 255]);
    c.disc(0.72, 0.35, 0.04, [255, 255, 255, 255]);
    c.rect(TAIL_LAMP, [70, 0, 0, 255]);
    c.rect([0.55, 0.55, 0.95, 0.7], [230, 30, 30, 255]);
    c.rect([0.0, 0.75, 1.0, 1.0], d.accent);
    c
}
