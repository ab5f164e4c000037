//! Level-of-detail cross-fades (`RenderOptions::lod_fade`): a change of model is drawn over six frames, the
//! new model through a growing screen door and the old one through its inverse, so every pixel the object
//! covers is drawn by exactly one of the two; without the option the models swap at once.

use glam::{Mat4, Vec3, Vec4};
use scanline_racer::render::{DrawList, Instance, LodSet, Method, RenderOptions, Renderer};

use crate::common::*;

const RED: Vec4 = Vec4::new(1.0, 0.0, 0.0, 1.0);
const BLUE: Vec4 = Vec4::new(0.0, 0.0, 1.0, 1.0);
const GREEN: Vec4 = Vec4::new(0.0, 1.0, 0.0, 1.0);

/// A square of side 2 centred on the origin, facing the camera, in one colour.
fn square(color: Vec4) -> scanline_racer::render::Mesh {
    let (a, b, c, d) =
        (Vec3::new(-1.0, -1.0, 0.0), Vec3::new(1.0, -1.0, 0.0), Vec3::new(1.0, 1.0, 0.0), Vec3::new(-1.0, 1.0, 0.0));
    tri_mesh(&[[a, b, c], [a, c, d]], &[color], true)
}

/// The frames of an object whose projected size drops from the close model's range into the middle
/// model's after the first frame, then stays: `(red, blue, other)` pixel counts of each frame.
fn frames(options: &RenderOptions, n: usize) -> Vec<(usize, usize, usize)> {
    pictures(options, n)
        .iter()
        .map(|frame| {
            let count = |c: u32| frame.iter().filter(|&&p| p == c).count();
            let (red, blue) = (count(0x00ff_0000), count(0x0000_00ff));
            (red, blue, frame.iter().filter(|&&p| p != 0 && p != 0x00ff_0000 && p != 0x0000_00ff).count())
        })
        .collect()
}

/// The frames [`frames`] counts, as drawn.
fn pictures(options: &RenderOptions, n: usize) -> Vec<Vec<u32>> {
    let (w, h) = (64usize, 64usize);
    let camera = pixel_camera(w, h);
    let meshes = [square(RED), square(BLUE), square(GREEN)];
    // The close model above 40 px, the middle one above 8 px.
    let sets = [LodSet { meshes: [0, 1, 2], switch_px: [40.0, 8.0] }];
    let mut renderer = Renderer::new();
    (0..n)
        .map(|k| {
            // A radius of 24 px (close), then 16 px (middle, past the hysteresis band), at the frame's centre.
            let scale = if k == 0 { 24.0 / 2f32.sqrt() } else { 16.0 / 2f32.sqrt() };
            let model = Mat4::from_translation(Vec3::new(32.0, 32.0, 0.0)) * Mat4::from_scale(Vec3::splat(scale));
            let instances = [Instance::of_lod_set(0, model)];
            let list =
                DrawList { meshes: &meshes, textures: &[], instances: &instances, lod_sets: &sets, view_lists: None };
            let mut frame = vec![0u32; w * h];
            renderer.render(&mut frame, w, h, &camera, &list, options).unwrap();
            frame
        })
        .collect()
}

#[test]
fn a_change_of_model_fades_over_six_frames_with_every_pixel_drawn_by_exactly_one_model() {
    for method in [Method::ZBuffer, Method::BucketFar, Method::BucketNear, Method::Sort] {
        let base = RenderOptions { method, background: Some(0), threads: 1, ..RenderOptions::default() };
        let swap = frames(&base, 8);
        let fade = frames(&RenderOptions { lod_fade: true, ..base }, 8);
        // The square after the change: every pixel it covers is counted, in one colour or the other.
        let area = swap[1].1;
        assert!(area > 300, "{method}: {swap:?}");
        assert!(swap[0].0 > area, "{method}: the close model first, larger");
        assert!(swap[1..].iter().all(|f| *f == (0, area, 0)), "{method}: swapped at once: {swap:?}");
        assert_eq!(fade[0], swap[0], "{method}");
        // Every pixel of the square, red or blue, nothing else; the blue share grows by quarters.
        for (k, f) in fade.iter().enumerate().skip(1) {
            assert_eq!((f.0 + f.1, f.2), (area, 0), "{method} frame {k}: {fade:?}");
        }
        let blue: Vec<f64> = fade[1..].iter().map(|f| f.1 as f64 / area as f64).collect();
        for (k, want) in [0.25, 0.25, 0.5, 0.5, 0.75, 0.75, 1.0].iter().enumerate() {
            assert!((blue[k] - want).abs() < 0.03, "{method} frame {}: {:.3} blue, want {want}", k + 1, blue[k]);
        }
    }
}

#[test]
fn a_fade_is_the_same_on_every_thread_count_and_with_supersampling() {
    let base = RenderOptions { background: Some(0), lod_fade: true, ..RenderOptions::default() };
    let one = frames(&RenderOptions { threads: 1, ..base }, 8);
    assert_eq!(frames(&RenderOptions { threads: 3, ..base }, 8), one);
    // 2x2 supersampling draws the doors at the doubled size: the shares are the same, the colours blend.
    let ssaa = frames(&RenderOptions { antialias: scanline_racer::render::Antialias::Supersample2x2, ..base }, 8);
    assert_eq!(ssaa[7].1, one[7].1, "the middle model alone after the fade");
}

#[test]
fn a_rotated_grid_frame_fades_once_a_frame_and_blends_the_doors_as_supersampling_does() {
    use scanline_racer::render::Antialias;
    let base = RenderOptions { background: Some(0), lod_fade: true, threads: 1, ..RenderOptions::default() };
    let plain = frames(&base, 8);
    let rgss = RenderOptions { antialias: Antialias::RotatedGrid, ..base };
    let pictures = pictures(&rgss, 8);
    let counts = frames(&rgss, 8);
    assert_eq!(frames(&RenderOptions { threads: 3, ..rgss }, 8), counts, "the same on three threads");
    // Each pass takes one cell of the doors' 2x2 blocks, and every 2x2 block of the 4x4 ranks holds one rank
    // of each quarter: inside the square every pixel is the same blend, a quarter, half, three quarters
    // blue as the fade goes, never red or blue alone until it ends.
    let area = plain[7].1;
    let blend = |blue: u32| (((255 * (4 - blue) + 2) / 4) << 16) | ((255 * blue + 2) / 4);
    for (k, blue) in [(1usize, 1u32), (2, 1), (3, 2), (4, 2), (5, 3), (6, 3)] {
        let inside = pictures[k].iter().filter(|&&p| p == blend(blue)).count();
        assert!(inside > area * 8 / 10, "frame {k}: {inside} of about {area} pixels {:06x}", blend(blue));
        assert_eq!((counts[k].0, counts[k].1), (0, 0), "frame {k}: {counts:?}");
    }
    // Six frames, as without the four passes: had each pass advanced the history, the fade would have ended
    // within the second frame.
    assert!(counts[7].0 == 0 && counts[7].1 > area * 8 / 10, "{counts:?}");
    assert!(counts[0].0 > area, "the close model first: {counts:?}");
}
