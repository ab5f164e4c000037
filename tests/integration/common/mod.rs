//! Helpers shared by the integration tests: a small deterministic RNG, an independent reference
//! rasterizer on the 1/16-pixel grid, and scene builders.

pub mod xvfb;

use glam::{Mat4, Vec2, Vec3, Vec4};
use scanline_racer::render::{
    Camera, DrawList, Instance, Material, Mesh, MeshBuilder, Projection, RenderOptions, Renderer, Stats, Texture,
    Vertex,
};

/// xorshift64*: deterministic, no dependencies, good enough for test geometry.
pub struct Rng(pub u64);

impl Rng {
    pub fn next_u64(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }
    /// Uniform in `lo..hi`.
    pub fn range(&mut self, lo: i64, hi: i64) -> i64 {
        lo + (self.next_u64() % (hi - lo) as u64) as i64
    }
    pub fn unit(&mut self) -> f32 {
        (self.next_u64() >> 40) as f32 / (1u64 << 24) as f32
    }
}

/// Reference coverage test, written independently of the renderer: edge functions on the 1/16 grid with
/// the top-left rule (a pixel centre on an edge belongs to the triangle when the edge is a top or left edge).
/// Points are `(x, y)` in 1/16 pixel, y down. Returns whether pixel `(px, py)`'s centre is covered.
pub fn ref_covers(tri: [(i64, i64); 3], px: i64, py: i64) -> bool {
    ref_covers_point(tri, (px * 16 + 8, py * 16 + 8))
}

/// [`ref_covers`] for any point `p` of the 1/16 grid (a coverage sample), by the same rule.
pub fn ref_covers_point(tri: [(i64, i64); 3], p: (i64, i64)) -> bool {
    let [a, b, c] = tri;
    let area = (b.0 - a.0) * (c.1 - a.1) - (b.1 - a.1) * (c.0 - a.0);
    if area == 0 {
        return false;
    }
    // Orient clockwise on screen (positive area with y down).
    let (b, c) = if area > 0 { (b, c) } else { (c, b) };
    [(a, b), (b, c), (c, a)].iter().all(|&(s, e)| {
        let (dx, dy) = (e.0 - s.0, e.1 - s.1);
        let f = dx * (p.1 - s.1) - dy * (p.0 - s.0);
        let top_left = dy < 0 || (dy == 0 && dx > 0);
        f > 0 || (f == 0 && top_left)
    })
}

/// Per-pixel count of reference-covered triangles over a `w` x `h` frame.
pub fn ref_counts(tris: &[[(i64, i64); 3]], w: usize, h: usize) -> Vec<u32> {
    let mut counts = vec![0u32; w * h];
    for t in tris {
        let xs = t.iter().map(|p| p.0);
        let ys = t.iter().map(|p| p.1);
        let x0 = ((xs.clone().min().unwrap_or(0) - 8).div_euclid(16)).max(0);
        let x1 = ((xs.max().unwrap_or(0) + 8).div_euclid(16) + 1).min(w as i64);
        let y0 = ((ys.clone().min().unwrap_or(0) - 8).div_euclid(16)).max(0);
        let y1 = ((ys.max().unwrap_or(0) + 8).div_euclid(16) + 1).min(h as i64);
        for y in y0..y1 {
            for x in x0..x1 {
                if ref_covers(*t, x, y) {
                    counts[y as usize * w + x as usize] += 1;
                }
            }
        }
    }
    counts
}

/// An orthographic camera under which world `(x, y)` maps exactly to pixel coordinates `(x, h - y)` when `w`
/// and `h` are powers of two: dyadic inputs project without rounding, so tests know every snapped vertex.
/// The eye is at world `z = 1000` looking down `-Z`: larger world `z` is nearer.
pub fn pixel_camera(w: usize, h: usize) -> Camera {
    assert!(w.is_power_of_two() && h.is_power_of_two());
    let (hw, hh) = (w as f32 * 0.5, h as f32 * 0.5);
    Camera {
        view: Mat4::from_translation(Vec3::new(-hw, -hh, -1000.0)),
        projection: Projection::Orthographic { xmag: hw, ymag: hh, znear: 1.0, zfar: 3000.0 },
    }
}

/// World position for a pixel-space point `(x16, y16)` in 1/16 pixel (y down) at depth `z` (larger is nearer).
pub fn pix(x16: i64, y16: i64, h: usize, z: f32) -> Vec3 {
    Vec3::new(x16 as f32 / 16.0, h as f32 - y16 as f32 / 16.0, z)
}

/// A mesh of flat-coloured, double-sided triangles.
pub fn tri_mesh(tris: &[[Vec3; 3]], colors: &[Vec4], double_sided: bool) -> Mesh {
    let mut b = MeshBuilder::new();
    let m = b.material(Material { double_sided, ..Material::default() });
    for (i, t) in tris.iter().enumerate() {
        let c = colors[i % colors.len()];
        let idx: Vec<u32> = t.iter().map(|&p| b.vertex(Vertex { position: p, uv: Vec2::ZERO, color: c })).collect();
        b.polygon(&idx, m);
    }
    b.build().expect("valid mesh")
}

/// Renders meshes with identity model matrices.
pub fn render(
    meshes: &[Mesh],
    textures: &[Texture],
    camera: &Camera,
    w: usize,
    h: usize,
    options: &RenderOptions,
) -> (Vec<u32>, Stats) {
    let instances: Vec<Instance> = (0..meshes.len()).map(|mesh| Instance::new(mesh, Mat4::IDENTITY)).collect();
    let mut frame = vec![0u32; w * h];
    let stats = Renderer::new()
        .render(
            &mut frame,
            w,
            h,
            camera,
            &DrawList { meshes, textures, instances: &instances, lod_sets: &[], view_lists: None },
            options,
        )
        .expect("render");
    (frame, stats)
}

/// Reads a PNG as `0x00RRGGBB` pixels.
pub fn read_png(path: &std::path::Path) -> Option<(Vec<u32>, usize, usize)> {
    let img = image::open(path).ok()?.to_rgb8();
    let (w, h) = (img.width() as usize, img.height() as usize);
    let px = img.pixels().map(|p| (u32::from(p[0]) << 16) | (u32::from(p[1]) << 8) | u32::from(p[2])).collect();
    Some((px, w, h))
}

/// Writes `0x00RRGGBB` pixels as PNG.
pub fn write_png(path: &std::path::Path, px: &[u32], w: usize, h: usize) {
    let rgb: Vec<u8> = px.iter().flat_map(|&p| [(p >> 16) as u8, (p >> 8) as u8, p as u8]).collect();
    if let Some(dir) = path.parent() {
        let _ = std::fs::create_dir_all(dir);
    }
    image::save_buffer(path, &rgb, w as u32, h as u32, image::ColorType::Rgb8).expect("write png");
}

/// Largest per-channel difference between two pixels.
pub fn channel_diff(a: u32, b: u32) -> u32 {
    (0..3).map(|s| ((a >> (8 * s)) & 0xff).abs_diff((b >> (8 * s)) & 0xff)).max().unwrap_or(0)
}

/// Path to the public glTF sample models vendored into the repository (licences in their `LICENSES.md`).
pub fn samples() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/samples")
}

/// The circuit's centre line from the shipped assets.
pub fn circuit() -> std::sync::Arc<scanline_racer::game::Track> {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/track/circuit/centerline.json");
    let text = std::fs::read_to_string(path).expect("centre line");
    std::sync::Arc::new(scanline_racer::game::Track::from_json(&text).expect("valid centre line"))
}

/// Records `ticks` ticks of a three-lap race whose player is driven by a scripted (AI) driver, through the
/// same recording step the window uses; returns the checksums written.
pub fn record_trace(path: &std::path::Path, ticks: u64) -> Vec<(u64, u64)> {
    use scanline_racer::game::ai::{Driver, drive};
    use scanline_racer::shell::race::{CHECKSUM_EVERY, header_for};
    let mut w = scanline_racer::game::World::with_laps(circuit(), 8, 3);
    let mut rec =
        scanline_racer::input::trace::TraceWriter::create(path, &header_for(&w, "circuit")).expect("create trace");
    let mut sums = vec![];
    for _ in 0..ticks {
        let c = drive(&Driver::field(3), 0, &w.cars, &w.track, &w.params[0]);
        scanline_racer::input::replay::step_recorded(&mut w, c, Some(&mut rec), CHECKSUM_EVERY).expect("record");
        if w.tick.is_multiple_of(u64::from(CHECKSUM_EVERY)) {
            sums.push((w.tick, w.checksum()));
        }
    }
    sums
}

/// Reads an X window dump (`xwd -root`) of 24/32-bit ZPixmap as `0x00RRGGBB` pixels.
pub fn read_xwd(bytes: &[u8]) -> Option<(Vec<u32>, usize, usize)> {
    let field = |i: usize| -> Option<u32> { Some(u32::from_be_bytes(bytes.get(4 * i..4 * i + 4)?.try_into().ok()?)) };
    let header_size = field(0)? as usize;
    let (format, width, height) = (field(2)?, field(4)? as usize, field(5)? as usize);
    let (byte_order, bits_per_pixel, bytes_per_line) = (field(7)?, field(11)?, field(12)? as usize);
    let ncolors = field(19)? as usize;
    if format != 2 || bits_per_pixel != 32 {
        return None;
    }
    let data = bytes.get(header_size + 12 * ncolors..)?;
    let mut px = Vec::with_capacity(width * height);
    for y in 0..height {
        for x in 0..width {
            let p = data.get(y * bytes_per_line + 4 * x..y * bytes_per_line + 4 * x + 4)?;
            let v = if byte_order == 0 {
                u32::from_le_bytes(p.try_into().ok()?)
            } else {
                u32::from_be_bytes(p.try_into().ok()?)
            };
            px.push(v & 0x00ff_ffff);
        }
    }
    Some((px, width, height))
}

/// The address space a child of [`run_bounded`] may take, in MiB: a runaway allocation (a file read without
/// a budget, `/dev/zero`) fails the child at once instead of swapping the machine.
pub const CHILD_MEMORY_MIB: u64 = 2048;

/// Runs `cmd` with its output captured, its address space limited to [`CHILD_MEMORY_MIB`] (`ulimit -v`,
/// with `MALLOC_ARENA_MAX=2` so that the limit does not depend on the core count), and kills it after
/// `secs` seconds: a child still running then fails the test, naming `what` (a hang is a failure, never a
/// stuck test run).
pub fn run_bounded(cmd: &mut std::process::Command, secs: u64, what: &str) -> std::process::Output {
    use std::io::Read;
    use std::process::Stdio;
    let mut bounded = std::process::Command::new("sh");
    bounded
        .arg("-c")
        .arg("ulimit -v \"$0\" && exec \"$@\"")
        .arg((CHILD_MEMORY_MIB * 1024).to_string())
        .arg(cmd.get_program())
        .args(cmd.get_args())
        .env("MALLOC_ARENA_MAX", "2");
    for (k, v) in cmd.get_envs() {
        match v {
            Some(v) => bounded.env(k, v),
            None => bounded.env_remove(k),
        };
    }
    if let Some(d) = cmd.get_current_dir() {
        bounded.current_dir(d);
    }
    let mut child = bounded.stdin(Stdio::null()).stdout(Stdio::piped()).stderr(Stdio::piped()).spawn().expect("spawn");
    let pipe = |mut r: Box<dyn Read + Send>| {
        std::thread::spawn(move || {
            let mut v = vec![];
            let _ = r.read_to_end(&mut v);
            v
        })
    };
    let out = pipe(Box::new(child.stdout.take().expect("stdout")));
    let err = pipe(Box::new(child.stderr.take().expect("stderr")));
    let deadline = std::time::Instant::now() + std::time::Duration::from_secs(secs);
    let status = loop {
        if let Some(st) = child.try_wait().expect("wait") {
            break st;
        }
        if std::time::Instant::now() > deadline {
            let _ = child.kill();
            let _ = child.wait();
            let err = String::from_utf8_lossy(&err.join().unwrap_or_default()).into_owned();
            panic!("{what}: still running after {secs} s, killed (stderr: {err})");
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    };
    std::process::Output { status, stdout: out.join().unwrap_or_default(), stderr: err.join().unwrap_or_default() }
}

/// Asserts that `o` failed with exit status 1 and exactly one stderr line containing every one of `needles`,
/// and no panic.
pub fn assert_one_line(o: &std::process::Output, needles: &[&str]) {
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!err.contains("panicked"), "panic: {err}");
    assert_eq!(o.status.code(), Some(1), "stderr: {err}");
    assert_eq!(err.trim_end().lines().count(), 1, "expected one line, got: {err}");
    for n in needles {
        assert!(err.contains(n), "expected '{n}' in: {err}");
    }
}

/// Makes a FIFO at `path` (replacing whatever is there).
pub fn mkfifo(path: &std::path::Path) {
    let _ = std::fs::remove_file(path);
    let ok = std::process::Command::new("mkfifo").arg(path).status().map(|s| s.success()).unwrap_or(false);
    assert!(ok, "mkfifo {} failed", path.display());
}

/// A fresh copy of the repository's `assets/` folder at `dir` (for tests that break one of its files).
pub fn copy_assets(dir: &std::path::Path) {
    fn copy(from: &std::path::Path, to: &std::path::Path) {
        std::fs::create_dir_all(to).unwrap();
        for e in std::fs::read_dir(from).unwrap() {
            let e = e.unwrap();
            let (src, dst) = (e.path(), to.join(e.file_name()));
            if e.file_type().unwrap().is_dir() {
                copy(&src, &dst);
            } else {
                std::fs::copy(&src, &dst).unwrap();
            }
        }
    }
    let _ = std::fs::remove_dir_all(dir);
    copy(&std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets"), dir);
}

/// Writes a trace of a three-lap race of eight cars on the shipped circuit in which the player never moves
/// for `ticks` ticks, and no checksums: a long trace made in a moment (5 bytes a tick).
pub fn write_idle_trace(path: &std::path::Path, ticks: u64) {
    use scanline_racer::shell::race::header_for;
    let w = scanline_racer::game::World::with_laps(circuit(), 8, 3);
    let mut rec =
        scanline_racer::input::trace::TraceWriter::create(path, &header_for(&w, "circuit")).expect("create trace");
    for _ in 0..ticks {
        rec.controls(scanline_racer::game::Controls::default()).expect("write");
    }
    rec.finish().expect("flush");
}

/// Every file below `dir`, by its path relative to `dir`, with its bytes (for comparing generated trees).
pub fn files_under(dir: &std::path::Path) -> std::collections::BTreeMap<std::path::PathBuf, Vec<u8>> {
    let mut out = std::collections::BTreeMap::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                stack.push(p);
            } else {
                out.insert(p.strip_prefix(dir).unwrap().to_path_buf(), std::fs::read(&p).unwrap());
            }
        }
    }
    out
}
