//! The renderer's workers: the thread that calls `render` is one of them, and a renderer drawn from
//! other threads, rebuilt for other thread counts or made again on the same thread draws the same frames.

use crate::common::*;
use scanline_racer::render::{Camera, Method, RenderOptions, Renderer};

/// The duck at 160x120 with `threads` threads: the frame and the pixels shaded.
fn draw(
    r: &mut Renderer,
    scene: &scanline_racer::asset::LoadedScene,
    camera: &Camera,
    threads: usize,
) -> (Vec<u32>, u64) {
    let (w, h) = (160usize, 120usize);
    let mut frame = vec![0u32; w * h];
    let o = RenderOptions { method: Method::ZBuffer, threads, ..RenderOptions::default() };
    let stats = r.render(&mut frame, w, h, camera, &scene.draw_list(), &o).unwrap();
    (frame, stats.pixels_shaded)
}

#[test]
fn a_renderer_draws_the_same_frames_from_any_thread_with_any_pool() {
    let scene = scanline_racer::asset::load(&samples().join("Duck/Duck.gltf")).expect("Duck loads");
    let camera = scene.framing_camera(160.0 / 120.0);
    // A thread of its own, so that it is in no pool when the first renderer asks for its workers.
    std::thread::scope(|s| {
        s.spawn(|| {
            let reference = draw(&mut Renderer::new(), &scene, &camera, 1);
            assert!(reference.1 > 2_000, "the duck covers part of the frame ({} pixels)", reference.1);
            let mut first = Renderer::new();
            // Its pool has this thread as a worker; then one of three threads, then two again.
            for threads in [2, 2, 3, 2, 1, 2] {
                assert!(draw(&mut first, &scene, &camera, threads) == reference, "{threads} threads, same thread");
            }
            // A second renderer on the same thread while the first lives, drawn in turn with it.
            let mut second = Renderer::new();
            for _ in 0..2 {
                assert!(draw(&mut second, &scene, &camera, 2) == reference, "a second renderer");
                assert!(draw(&mut first, &scene, &camera, 2) == reference, "the first after the second");
            }
            // The first renderer drawn from another thread, then back here.
            let (scene_ref, camera_ref, reference_ref) = (&scene, &camera, &reference);
            let first = std::thread::scope(|inner| {
                inner
                    .spawn(move || {
                        let mut moved = first;
                        for threads in [2, 3] {
                            let frame = draw(&mut moved, scene_ref, camera_ref, threads);
                            assert!(frame == *reference_ref, "moved, {threads}");
                        }
                        moved
                    })
                    .join()
                    .unwrap()
            });
            let mut first = first;
            assert!(draw(&mut first, &scene, &camera, 2) == reference, "back on its first thread");
            // Both dropped: a renderer made again on this thread.
            drop((first, second));
            assert!(draw(&mut Renderer::new(), &scene, &camera, 2) == reference, "a renderer made again");
        });
    });
}
