#!/usr/bin/env python3
"""How the frame time grows with the work, ours and Mesa's llvmpipe side by side, 1 and 2 threads.

    scripts/scaling.py [--out docs] [--rounds 2] [--repeat 10] [--binary target/release/scanline-racer]

Two sweeps, each point timed by scripts/llvmpipe_compare.py (the two renderers alternated --rounds times,
each side's best median of --repeat frames kept):

- pixels: the demo race's tick 3600 exported at 320x240 up to 3840x2160 (the same objects, more pixels);
- polygons: 1,000 to 1,000,000 small flat triangles (about 4.5 pixels each, random depths, a third of them
  in front of the rest on average) at 640x480, written as a GLB here (`small_triangles_glb`).

Writes OUT/scaling.csv and the charts OUT/scaling-pixels.png and OUT/scaling-polygons.png (log-log), and
prints each line's slope: the exponent of time against work, fitted over the sweep's upper half (where
fixed costs no longer dominate). A slope of 1 is a cost that grows as the work does; above 1 grows faster.
Charts are drawn with Pillow, which llvmpipe_compare.py installs with pip on first use, with numpy.
"""
import argparse, csv, json, math, os, struct, subprocess, sys, tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
SIZES = [(320, 240), (640, 480), (1280, 720), (1920, 1080), (2560, 1440), (3840, 2160)]
COUNTS = [1_000, 3_000, 10_000, 30_000, 100_000, 300_000, 1_000_000]


def small_triangles_glb(path, n, width=640, height=480, seed=1):
    """Writes a GLB of `n` flat triangles about 3x3 pixels (4.5 pixels of area) each on a `width` x
    `height` frame, spread over the frame at random depths 5-15 in front of a camera at the origin."""
    import numpy as np
    rng = np.random.default_rng(seed)
    yfov = 1.0
    half = math.tan(yfov / 2.0)
    aspect = width / height
    depth = rng.uniform(5.0, 15.0, n)
    sx = rng.uniform(-1.0, 1.0, n) * half * aspect * depth
    sy = rng.uniform(-1.0, 1.0, n) * half * depth
    side = 3.0 * 2.0 * half * depth / height  # three pixels at that depth
    pos = np.zeros((n, 3, 3), dtype=np.float32)
    pos[:, :, 2] = -depth[:, None]
    pos[:, 0, 0], pos[:, 0, 1] = sx, sy
    pos[:, 1, 0], pos[:, 1, 1] = sx + side, sy
    pos[:, 2, 0], pos[:, 2, 1] = sx, sy + side
    pos = pos.reshape(-1, 3)
    uv = np.zeros((3 * n, 2), dtype=np.float32)
    col = np.repeat(rng.uniform(0.1, 1.0, (n, 4)).astype(np.float32), 3, axis=0)
    col[:, 3] = 1.0
    idx = np.arange(3 * n, dtype=np.uint32)
    blobs = [pos.tobytes(), uv.tobytes(), col.tobytes(), idx.tobytes()]
    views, offset = [], 0
    for b in blobs:
        views.append({"buffer": 0, "byteOffset": offset, "byteLength": len(b)})
        offset += len(b)
    acc = [
        {"bufferView": 0, "componentType": 5126, "count": 3 * n, "type": "VEC3",
         "min": pos.min(axis=0).tolist(), "max": pos.max(axis=0).tolist()},
        {"bufferView": 1, "componentType": 5126, "count": 3 * n, "type": "VEC2"},
        {"bufferView": 2, "componentType": 5126, "count": 3 * n, "type": "VEC4"},
        {"bufferView": 3, "componentType": 5125, "count": 3 * n, "type": "SCALAR"},
    ]
    doc = {
        "asset": {"version": "2.0", "generator": "scripts/scaling.py"},
        "scene": 0, "scenes": [{"nodes": [0, 1]}],
        "nodes": [{"mesh": 0, "name": "triangles"},
                  {"camera": 0, "name": "frame camera", "matrix": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1, "COLOR_0": 2}, "indices": 3,
                                    "material": 0}]}],
        "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 1]}, "doubleSided": True}],
        "cameras": [{"type": "perspective", "perspective": {"yfov": yfov, "znear": 0.5, "zfar": 100.0,
                                                             "aspectRatio": aspect}}],
        "accessors": acc, "bufferViews": views, "buffers": [{"byteLength": offset}],
    }
    js = json.dumps(doc).encode()
    js += b" " * (-len(js) % 4)
    binary = b"".join(blobs)
    binary += b"\0" * (-len(binary) % 4)
    with open(path, "wb") as f:
        f.write(struct.pack("<4sII", b"glTF", 2, 12 + 8 + len(js) + 8 + len(binary)))
        f.write(struct.pack("<I4s", len(js), b"JSON") + js)
        f.write(struct.pack("<I4s", len(binary), b"BIN\0") + binary)


def compare(glb, w, h, threads, a):
    """Both renderers' best medians (ms) on `glb` at `w` x `h` with `threads`."""
    cmd = [sys.executable, os.path.join(HERE, "llvmpipe_compare.py"), glb, "--width", str(w), "--height", str(h),
           "--threads", str(threads), "--rounds", str(a.rounds), "--repeat", str(a.repeat), "--binary", a.binary,
           "--json"]
    out = subprocess.run(cmd, capture_output=True, text=True, check=True)
    d = json.loads(out.stdout)
    return d["ours_ms"], d["llvmpipe_ms"]


def slope(points):
    """The least-squares slope of log(time) against log(work) over the upper half of `points`."""
    pts = sorted(points)[len(points) // 2 - (1 if len(points) % 2 == 0 else 0):]
    xs = [math.log(x) for x, _ in pts]
    ys = [math.log(y) for _, y in pts]
    mx, my = sum(xs) / len(xs), sum(ys) / len(ys)
    return sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sum((x - mx) ** 2 for x in xs)


def chart(path, title, xlabel, series):
    """A log-log chart of `series` ({label: [(x, ms)]}) as a PNG."""
    from PIL import Image, ImageDraw
    W, H, L, R, T, B = 900, 560, 80, 250, 50, 60
    img = Image.new("RGB", (W, H), "white")
    d = ImageDraw.Draw(img)
    xs = [x for s in series.values() for x, _ in s]
    ys = [y for s in series.values() for _, y in s]
    x0, x1 = math.floor(math.log10(min(xs))), math.ceil(math.log10(max(xs)))
    y0, y1 = math.floor(math.log10(min(ys))), math.ceil(math.log10(max(ys)))
    px = lambda x: L + (math.log10(x) - x0) / (x1 - x0) * (W - L - R)
    py = lambda y: H - B - (math.log10(y) - y0) / (y1 - y0) * (H - T - B)
    for e in range(x0, x1 + 1):
        d.line([(px(10 ** e), T), (px(10 ** e), H - B)], fill=(225, 225, 225))
        d.text((px(10 ** e) - 12, H - B + 6), f"1e{e}", fill="black")
    for e in range(y0, y1 + 1):
        d.line([(L, py(10 ** e)), (W - R, py(10 ** e))], fill=(225, 225, 225))
        d.text((L - 50, py(10 ** e) - 6), f"{10 ** e:g} ms", fill="black")
    d.rectangle([L, T, W - R, H - B], outline="black")
    d.text((L, 15), title, fill="black")
    d.text(((L + W - R) // 2 - 40, H - 25), xlabel, fill="black")
    colours = [(200, 40, 40), (240, 140, 40), (40, 80, 200), (60, 170, 220)]
    for i, (label, pts) in enumerate(series.items()):
        c = colours[i % len(colours)]
        pts = sorted(pts)
        d.line([(px(x), py(y)) for x, y in pts], fill=c, width=2)
        for x, y in pts:
            d.ellipse([px(x) - 3, py(y) - 3, px(x) + 3, py(y) + 3], fill=c)
        d.line([(W - R + 15, T + 20 + i * 22), (W - R + 40, T + 20 + i * 22)], fill=c, width=3)
        d.text((W - R + 46, T + 14 + i * 22), f"{label}: slope {slope(pts):.2f}", fill="black")
    img.save(path)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out", default=os.path.join(ROOT, "docs"))
    ap.add_argument("--rounds", type=int, default=2)
    ap.add_argument("--repeat", type=int, default=10)
    ap.add_argument("--binary", default=os.path.join(ROOT, "target", "release", "scanline-racer"))
    a = ap.parse_args()
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for w, h in SIZES:
            glb = os.path.join(tmp, f"frame-{w}x{h}.glb")
            subprocess.run([a.binary, "export-frame", os.path.join(ROOT, "assets/replays/demo-race.trace"),
                            "--tick", "3600", "--width", str(w), "--height", str(h), "--out", glb],
                           check=True, capture_output=True)
            for t in (1, 2):
                ours, theirs = compare(glb, w, h, t, a)
                rows.append(("pixels", w * h, f"{w}x{h}", t, ours, theirs))
                print(f"pixels {w}x{h} {t}t: ours {ours:.3f} ms, llvmpipe {theirs:.3f} ms", flush=True)
            os.remove(glb)
        for n in COUNTS:
            glb = os.path.join(tmp, f"triangles-{n}.glb")
            small_triangles_glb(glb, n)
            for t in (1, 2):
                ours, theirs = compare(glb, 640, 480, t, a)
                rows.append(("polygons", n, str(n), t, ours, theirs))
                print(f"polygons {n} {t}t: ours {ours:.3f} ms, llvmpipe {theirs:.3f} ms", flush=True)
            os.remove(glb)
    os.makedirs(a.out, exist_ok=True)
    with open(os.path.join(a.out, "scaling.csv"), "w", newline="") as f:
        out = csv.writer(f)
        out.writerow(["sweep", "work", "label", "threads", "ours_ms", "llvmpipe_ms", "ratio"])
        for s, x, label, t, o, l in rows:
            out.writerow([s, x, label, t, f"{o:.3f}", f"{l:.3f}", f"{l / o:.2f}"])
    for sweep, title, xlabel in [("pixels", "Frame time against pixels (demo race, tick 3600)", "pixels"),
                                 ("polygons", "Frame time against small triangles (640x480)", "triangles")]:
        series = {}
        for s, x, _, t, o, l in rows:
            if s == sweep:
                series.setdefault(f"ours, {t} thread{'s' if t > 1 else ''}", []).append((x, o))
                series.setdefault(f"llvmpipe, {t} thread{'s' if t > 1 else ''}", []).append((x, l))
        order = sorted(series, key=lambda k: (not k.startswith("ours"), k))
        series = {k: series[k] for k in order}
        for k, pts in series.items():
            print(f"{sweep}: {k}: slope {slope(pts):.2f}")
        chart(os.path.join(a.out, f"scaling-{sweep}.png"), title, xlabel, series)


if __name__ == "__main__":
    main()
