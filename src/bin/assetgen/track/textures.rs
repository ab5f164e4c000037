//! The circuit's materials ([`Mats`]) and the painting of its PNG textures.

use std::path::Path;

use super::util::Rng;
use crate::gltf_out::{Doc, WrapMode};
use crate::paint::Canvas;

/// Material indices.
pub(super) struct Mats {
    pub(super) road: usize,
    pub(super) kerb: usize,
    pub(super) grass: usize,
    pub(super) gravel: usize,
    pub(super) armco: usize,
    pub(super) tyres: usize,
    pub(super) concrete: usize,
    pub(super) parapet: usize,
    pub(super) chequer: usize,
    pub(super) crowd: usize,
    pub(super) windows: usize,
    pub(super) roof: usize,
    pub(super) canopy: usize,
    pub(super) paint: usize,
    pub(super) tree: usize,
    pub(super) hills: usize,
    /// Bare rock on steep and high ground (the grass where the course has none).
    pub(super) rock: usize,
}

impl Mats {
    /// The materials; on a street course (`streets`) the "grass" is pavement, and a course in the hills
    /// (`rocky`) has rock.
    pub(super) fn new(doc: &mut Doc, streets: bool, rocky: bool) -> Mats {
        let mut tex = |name: &str, wrap| doc.texture(&format!("{name}.png"), wrap);
        let t_asphalt = tex("asphalt", WrapMode::Repeat);
        let t_kerb = tex("kerb", WrapMode::Repeat);
        let t_grass = tex(if streets { "pavement" } else { "grass" }, WrapMode::Repeat);
        let t_gravel = tex("gravel", WrapMode::Repeat);
        let t_armco = tex("armco", WrapMode::Repeat);
        let t_tyres = tex("tyres", WrapMode::Repeat);
        let t_concrete = tex("concrete", WrapMode::Repeat);
        let t_chequer = tex("chequer", WrapMode::Repeat);
        let t_crowd = tex("crowd", WrapMode::Repeat);
        let t_windows = tex("windows", WrapMode::Repeat);
        let t_tree = tex("trees", WrapMode::Clamp);
        let t_rock = rocky.then(|| tex("rock", WrapMode::Repeat));
        let white = glam::Vec4::ONE;
        let mut mats = Mats {
            road: doc.material("asphalt", white, Some(t_asphalt), false, None),
            kerb: doc.material("kerb", white, Some(t_kerb), false, None),
            grass: doc.material(if streets { "pavement" } else { "grass" }, white, Some(t_grass), false, None),
            gravel: doc.material("gravel", white, Some(t_gravel), false, None),
            armco: doc.material("armco", white, Some(t_armco), true, Some(0.5)),
            tyres: doc.material("tyre wall", white, Some(t_tyres), true, None),
            concrete: doc.material("concrete", white, Some(t_concrete), false, None),
            parapet: doc.material("parapet", white, Some(t_concrete), true, None),
            chequer: doc.material("chequer", white, Some(t_chequer), false, None),
            crowd: doc.material("crowd", white, Some(t_crowd), false, None),
            windows: doc.material("windows", white, Some(t_windows), false, None),
            roof: doc.material("roof", glam::Vec4::new(0.42, 0.43, 0.46, 1.0), None, false, None),
            canopy: doc.material("canopy", glam::Vec4::new(0.85, 0.86, 0.88, 1.0), None, true, None),
            paint: doc.material("paint", glam::Vec4::new(0.95, 0.95, 0.93, 1.0), None, false, None),
            tree: doc.material("trees", white, Some(t_tree), true, Some(0.5)),
            hills: doc.material("hills", white, None, false, None),
            rock: 0,
        };
        mats.rock = t_rock.map_or(mats.grass, |t| doc.material("rock", white, Some(t), false, None));
        mats
    }
}

fn shade(c: [u8; 3], d: i32) -> [u8; 4] {
    let f = |v: u8| (i32::from(v) + d).clamp(0, 255) as u8;
    [f(c[0]), f(c[1]), f(c[2]), 255]
}

/// A canvas of `base` with per-pixel grain of +-`amp`.
fn grain(size: u32, base: [u8; 3], amp: i32, rng: &mut Rng) -> Canvas {
    let mut c = Canvas::new(size, size, [0, 0, 0, 255]);
    for y in 0..size as i32 {
        for x in 0..size as i32 {
            let d = rng.int(-amp, amp);
            c.set(x, y, shade(base, d));
        }
    }
    c
}

/// Writes the course's textures into `dir`: the circuit's set, and on a street course (`streets`) the
/// pavement too.
pub(super) fn write_textures(dir: &Path, streets: bool, rocky: bool) -> std::io::Result<()> {
    let mut rng = Rng::new(0x7e57_0001);
    let rng = &mut rng;
    // Asphalt: 128 px across the 12 m road, white edge lines, darker wheel tracks.
    let mut asphalt = grain(128, [84, 84, 88], 9, rng);
    for y in 0..128 {
        for x in 0..128 {
            let g = rng.int(-8, 8);
            if (3..7).contains(&x) || (121..125).contains(&x) {
                asphalt.set(x, y, shade([226, 226, 220], g));
            } else if (26..40).contains(&x) || (88..102).contains(&x) {
                asphalt.set(x, y, shade([74, 74, 78], g));
            }
        }
    }
    asphalt.save(&dir.join("asphalt.png"))?;
    // Kerb: red and white stripes along the track, the outer quarter a shade darker.
    let mut kerb = Canvas::new(64, 64, [0, 0, 0, 255]);
    for y in 0..64 {
        for x in 0..64 {
            let base = if y < 32 { [206, 36, 30] } else { [240, 240, 236] };
            kerb.set(x, y, shade(base, rng.int(-6, 6) - if x >= 48 { 30 } else { 0 }));
        }
    }
    kerb.save(&dir.join("kerb.png"))?;
    grain(64, [74, 128, 54], 7, rng).save(&dir.join("grass.png"))?;
    let mut gravel = grain(64, [196, 180, 144], 16, rng);
    for _ in 0..90 {
        let (x, y) = (rng.int(0, 63), rng.int(0, 63));
        gravel.set(x, y, [150, 136, 110, 255]);
        gravel.set(x + 1, y, [226, 214, 186, 255]);
    }
    gravel.save(&dir.join("gravel.png"))?;
    armco_texture(rng).save(&dir.join("armco.png"))?;
    tyres_texture(rng).save(&dir.join("tyres.png"))?;
    let mut concrete = grain(64, [172, 170, 164], 8, rng);
    for i in 0..64 {
        concrete.set(i, 0, [120, 118, 114, 255]);
        concrete.set(0, i, [120, 118, 114, 255]);
    }
    concrete.save(&dir.join("concrete.png"))?;
    let mut chequer = Canvas::new(64, 64, [0, 0, 0, 255]);
    for y in 0..64 {
        for x in 0..64 {
            let c = if (x / 8 + y / 8) % 2 == 0 { [20, 20, 22, 255] } else { [238, 238, 236, 255] };
            chequer.set(x, y, c);
        }
    }
    chequer.save(&dir.join("chequer.png"))?;
    crowd_texture(rng).save(&dir.join("crowd.png"))?;
    windows_texture(rng).save(&dir.join("windows.png"))?;
    trees_texture(rng).save(&dir.join("trees.png"))?;
    if streets {
        pavement_texture(rng).save(&dir.join("pavement.png"))?;
    }
    if rocky {
        // Rock: grey-brown grain crossed by darker and lighter strata.
        let mut rock = grain(64, [132, 124, 112], 14, rng);
        for _ in 0..10 {
            let (y, d) = (rng.int(0, 63), rng.int(-34, 22));
            for x in 0..64 {
                let wave = y + (x / 9) % 2;
                rock.set(x, wave, shade([132, 124, 112], d + rng.int(-6, 6)));
            }
        }
        rock.save(&dir.join("rock.png"))?;
    }
    Ok(())
}

/// Pavement: grey slabs of 16 px with darker joints and a little grain (a repeat of 20 m: 1.25 m slabs).
fn pavement_texture(rng: &mut Rng) -> Canvas {
    let mut c = grain(256, [150, 148, 144], 6, rng);
    for y in 0..256 {
        for x in 0..256 {
            if x % 16 == 0 || y % 16 == 0 {
                c.set(x, y, shade([112, 110, 108], rng.int(-4, 4)));
            }
        }
    }
    c
}

/// Armco: two steel rails on posts every 4 m; transparent between (alpha mask).
fn armco_texture(rng: &mut Rng) -> Canvas {
    let mut c = Canvas::new(64, 64, [90, 90, 90, 0]);
    for y in 0..64 {
        for x in 0..64 {
            let rail = (4..22).contains(&y) || (26..42).contains(&y);
            if rail {
                let ridge = [0, 18, 30, 18, 0, -18][(y % 6) as usize];
                c.set(x, y, shade([176, 180, 186], ridge + rng.int(-5, 5)));
            } else if x < 5 && y >= 2 {
                c.set(x, y, shade([96, 98, 104], rng.int(-5, 5)));
            }
        }
    }
    c
}

/// Tyre wall: red and white belt on top, stacked tyres below.
fn tyres_texture(rng: &mut Rng) -> Canvas {
    let mut c = Canvas::new(64, 64, [28, 28, 30, 255]);
    for y in 0..64i32 {
        for x in 0..64i32 {
            let col = if y < 18 {
                if (x / 16) % 2 == 0 { [210, 40, 34] } else { [236, 236, 232] }
            } else {
                let (cx, cy) = ((x / 16) * 16 + 8, if y < 41 { 29 } else { 52 });
                let r2 = (x - cx) * (x - cx) + (y - cy) * (y - cy);
                if r2 < 16 {
                    [52, 52, 56]
                } else if r2 < 64 {
                    [18, 18, 20]
                } else {
                    [34, 34, 36]
                }
            };
            c.set(x, y, shade(col, rng.int(-4, 4)));
        }
    }
    c
}

/// Crowd: rows of spectators (shirts and heads) on dark seats; one row per 16 px.
fn crowd_texture(rng: &mut Rng) -> Canvas {
    let mut c = grain(128, [46, 52, 70], 6, rng);
    let shirts = [[200, 40, 40], [240, 200, 40], [40, 90, 200], [240, 240, 240], [40, 160, 70], [230, 120, 30]];
    let skins = [[236, 196, 160], [200, 150, 110], [140, 96, 66]];
    for row in 0..8 {
        let mut x = rng.int(0, 3);
        while x < 126 {
            let y = row * 16 + 3 + rng.int(0, 2);
            if rng.unit() < 0.88 {
                let shirt = shirts[rng.int(0, 5) as usize];
                let skin = skins[rng.int(0, 2) as usize];
                for dy in 0..8 {
                    for dx in 0..4 {
                        c.set(x + dx, y + 4 + dy, shade(shirt, rng.int(-10, 10)));
                    }
                }
                for dy in 0..3 {
                    for dx in 1..4 {
                        c.set(x + dx, y + dy, shade(skin, 0));
                    }
                }
            }
            x += 5 + rng.int(0, 2);
        }
    }
    c
}

/// Windows: one 4 m x 4 m wall panel with a divided window.
fn windows_texture(rng: &mut Rng) -> Canvas {
    let mut c = grain(64, [206, 200, 188], 5, rng);
    for y in 0..64 {
        for x in 0..64 {
            if y < 5 {
                c.set(x, y, shade([150, 146, 140], 0));
            } else if (14..48).contains(&y) && (6..58).contains(&x) && !(30..34).contains(&x) {
                let t = (y - 14) * 2;
                c.set(x, y, [60 + t as u8, 86 + t as u8, 112 + t as u8, 255]);
            } else if y == 48 && (4..60).contains(&x) {
                c.set(x, y, [120, 116, 110, 255]);
            }
        }
    }
    c
}

/// Trees: a broadleaf in the left half and a conifer in the right half (64 x 128 each), transparent around.
fn trees_texture(rng: &mut Rng) -> Canvas {
    let mut c = Canvas::new(128, 128, [60, 90, 50, 0]);
    let trunk = [96, 70, 46];
    for y in 84..128 {
        for x in 29..36 {
            c.set(x, y, shade(trunk, rng.int(-8, 8)));
        }
        for x in 94..98 {
            c.set(x, y, shade(trunk, rng.int(-8, 8)));
        }
    }
    // Broadleaf: a cluster of discs, lighter toward the top left.
    let discs = [(32.0, 50.0, 26.0), (18.0, 64.0, 15.0), (46.0, 64.0, 15.0), (32.0, 28.0, 19.0), (22.0, 40.0, 15.0)];
    for y in 0..128 {
        for x in 0..64 {
            let (fx, fy) = (x as f32 + 0.5, y as f32 + 0.5);
            let inside = discs
                .iter()
                .map(|&(cx, cy, r)| r - ((fx - cx).powi(2) + (fy - cy).powi(2)).sqrt())
                .fold(-1e9, f32::max);
            if inside > 0.0 && (inside > 3.0 || rng.unit() < 0.6) {
                let lit = ((64.0 - fx) * 0.3 + (90.0 - fy) * 0.5) as i32;
                c.set(x, y, shade([52, 102, 44], lit / 2 + rng.int(-14, 14)));
            }
        }
    }
    // Conifer: stacked tiers narrowing toward the top.
    for y in 6..116 {
        let fy = y as f32;
        let tier = ((fy - 6.0) % 22.0) / 22.0;
        let half = (fy - 6.0) / 110.0 * 27.0 * (0.7 + 0.3 * tier) + 1.0;
        for x in 64..128 {
            let dx = (x as f32 + 0.5 - 96.0).abs();
            if dx < half && (dx < half - 2.0 || rng.unit() < 0.6) {
                c.set(x, y, shade([34, 82, 48], (tier * 20.0) as i32 + rng.int(-12, 12)));
            }
        }
    }
    c
}
