#!/usr/bin/env python3
"""Renders an exported frame (scanline-racer export-frame) with Mesa's llvmpipe and with scanline-racer, at
the same size and thread count, and prints both times, their ratio and the share of pixels that match.

    scripts/llvmpipe_compare.py FRAME.glb [--width 1280] [--height 720] [--threads 2] [--repeat 30]
                                 [--method zbuffer] [--binary target/release/scanline-racer]
                                 [--msaa N] [--gl-filter nearest|nearest-mip|trilinear]
                                 [--aa A] [--filter F] [--mip M]

--msaa N draws llvmpipe into N-sample colour and depth buffers and resolves them (glBlitFramebuffer) into
the image that is read back, inside the timed frame. --gl-filter picks llvmpipe's texture filter: nearest
(no mip-maps), nearest-mip (GL_NEAREST_MIPMAP_NEAREST) or trilinear (GL_LINEAR_MIPMAP_LINEAR), with
mip-maps built by glGenerateMipmap at load. --aa, --filter and --mip are passed to our `render`.

llvmpipe runs headless on an EGL surfaceless context through moderngl (installed with pip on first use,
with numpy and Pillow). It draws what the renderer draws: unlit base colour x texture (nearest) x vertex
colour, alpha mask, back faces culled unless double-sided, depth test LESS, cleared to sky blue.
Timing: median and best of --repeat frames after 3 warm-up frames, each ended by glFinish; llvmpipe's
threads are set with LP_NUM_THREADS. Our time is `render --repeat N --stats json` on the same file. The two
run alternately --rounds times (default 3); each side's best median is kept and the ratio is of those
(the per-round ratios are printed too: two-thread timings on a 2-core machine vary from run to run).
Matching pixels: every channel within 8/255 (DESIGN's wrong-pixel measure).
"""
import argparse, json, os, struct, subprocess, sys, tempfile, time


def ensure(mods):
    missing = []
    for mod, pkg in mods:
        try:
            __import__(mod)
        except ImportError:
            missing.append(pkg)
    if missing:
        print("installing " + " ".join(missing) + " with pip ...", file=sys.stderr)
        subprocess.check_call([sys.executable, "-m", "pip", "install", "--quiet"] + missing)


def read_glb(path):
    data = open(path, "rb").read()
    if data[:4] != b"glTF":
        sys.exit("%s: not a GLB file" % path)
    jlen = struct.unpack_from("<I", data, 12)[0]
    doc = json.loads(data[20:20 + jlen])
    off = 20 + jlen
    blen = struct.unpack_from("<I", data, off)[0]
    return doc, data[off + 8: off + 8 + blen]


def accessor(doc, bin_, i, np):
    a = doc["accessors"][i]
    v = doc["bufferViews"][a["bufferView"]]
    comps = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4}[a["type"]]
    dtype = {5126: np.float32, 5125: np.uint32, 5123: np.uint16}[a["componentType"]]
    start = v.get("byteOffset", 0) + a.get("byteOffset", 0)
    arr = np.frombuffer(bin_, dtype=dtype, count=a["count"] * comps, offset=start)
    return arr.reshape(a["count"], comps) if comps > 1 else arr


def perspective(yfov, aspect, znear, zfar, np):
    f = 1.0 / np.tan(yfov / 2.0)
    m = np.zeros((4, 4), dtype=np.float64)
    m[0, 0] = f / aspect
    m[1, 1] = f
    m[3, 2] = -1.0
    if zfar:
        m[2, 2] = (zfar + znear) / (znear - zfar)
        m[2, 3] = 2 * zfar * znear / (znear - zfar)
    else:
        m[2, 2] = -1.0
        m[2, 3] = -2 * znear
    return m


VS = """#version 330
uniform mat4 mvp;
in vec3 in_pos; in vec2 in_uv; in vec4 in_col;
out vec2 uv; out vec4 col;
void main() { uv = in_uv; col = in_col; gl_Position = mvp * vec4(in_pos, 1.0); }"""
FS = """#version 330
uniform sampler2D tex; uniform bool textured; uniform vec4 base; uniform float cutoff;
in vec2 uv; in vec4 col; out vec4 frag;
void main() {
  vec4 c = base * col * (textured ? texture(tex, uv) : vec4(1.0));
  if (c.a < cutoff) discard;
  frag = vec4(c.rgb, 1.0);
}"""


def llvmpipe(glb, width, height, threads, msaa=0, gl_filter="nearest"):
    """Sets up the scene on an llvmpipe context; returns (time(repeat) -> (median, best), image(), renderer)."""
    os.environ["LIBGL_ALWAYS_SOFTWARE"] = "1"
    os.environ["GALLIUM_DRIVER"] = "llvmpipe"
    os.environ["LP_NUM_THREADS"] = str(threads)
    import numpy as np
    import moderngl
    from PIL import Image
    import io
    doc, bin_ = read_glb(glb)
    ctx = moderngl.create_standalone_context(backend="egl")
    prog = ctx.program(vertex_shader=VS, fragment_shader=FS)
    cam_node = next(n for n in doc["nodes"] if "camera" in n)
    world = np.array(cam_node["matrix"], dtype=np.float64).reshape(4, 4).T
    view = np.linalg.inv(world)
    p = doc["cameras"][cam_node["camera"]]["perspective"]
    proj = perspective(p["yfov"], width / height, p["znear"], p.get("zfar"), np)
    prog["mvp"].write((proj @ view).T.astype("f4").tobytes())
    textures = {}
    for i, t in enumerate(doc.get("textures", [])):
        img = doc["images"][t["source"]]
        v = doc["bufferViews"][img["bufferView"]]
        im = Image.open(io.BytesIO(bin_[v.get("byteOffset", 0): v.get("byteOffset", 0) + v["byteLength"]])).convert("RGBA")
        tex = ctx.texture(im.size, 4, im.tobytes())
        if gl_filter == "nearest":
            tex.filter = (moderngl.NEAREST, moderngl.NEAREST)
        else:
            tex.build_mipmaps()
            tex.filter = ((moderngl.NEAREST_MIPMAP_NEAREST, moderngl.NEAREST) if gl_filter == "nearest-mip"
                          else (moderngl.LINEAR_MIPMAP_LINEAR, moderngl.LINEAR))
        s = doc["samplers"][t["sampler"]]
        tex.repeat_x = s.get("wrapS", 10497) != 33071
        tex.repeat_y = s.get("wrapT", 10497) != 33071
        textures[i] = tex
    draws = []
    for prim in doc["meshes"][0]["primitives"]:
        at = prim["attributes"]
        buf = lambda i: ctx.buffer(accessor(doc, bin_, i, np).astype("f4").tobytes())
        ibo = ctx.buffer(accessor(doc, bin_, prim["indices"], np).astype("u4").tobytes())
        vao = ctx.vertex_array(prog, [(buf(at["POSITION"]), "3f", "in_pos"), (buf(at["TEXCOORD_0"]), "2f", "in_uv"),
                                      (buf(at["COLOR_0"]), "4f", "in_col")], index_buffer=ibo, index_element_size=4)
        m = doc["materials"][prim["material"]]
        pbr = m.get("pbrMetallicRoughness", {})
        tex = pbr.get("baseColorTexture", {}).get("index")
        cutoff = m.get("alphaCutoff", 0.5) if m.get("alphaMode") == "MASK" else -1.0
        draws.append((vao, textures.get(tex), tuple(pbr.get("baseColorFactor", [1, 1, 1, 1])), cutoff,
                      m.get("doubleSided", False)))
    fbo = ctx.framebuffer(ctx.renderbuffer((width, height)), ctx.depth_renderbuffer((width, height)))
    draw_fbo = fbo
    if msaa > 1:
        draw_fbo = ctx.framebuffer(ctx.renderbuffer((width, height), samples=msaa),
                                   ctx.depth_renderbuffer((width, height), samples=msaa))
    draw_fbo.use()
    ctx.enable(moderngl.DEPTH_TEST)
    ctx.depth_func = "<"
    ctx.front_face = "ccw"

    def frame():
        draw_fbo.use()
        draw_fbo.clear(135 / 255, 206 / 255, 235 / 255, 1.0, depth=1.0)
        for vao, tex, base, cutoff, double in draws:
            if double:
                ctx.disable(moderngl.CULL_FACE)
            else:
                ctx.enable(moderngl.CULL_FACE)
            prog["textured"] = tex is not None
            if tex is not None:
                tex.use(0)
                prog["tex"] = 0
            prog["base"] = base
            prog["cutoff"] = cutoff
            vao.render(moderngl.TRIANGLES)
        if draw_fbo is not fbo:
            ctx.copy_framebuffer(fbo, draw_fbo)
        ctx.finish()

    def timed(repeat):
        for _ in range(3):
            frame()
        times = []
        for _ in range(repeat):
            t = time.perf_counter()
            frame()
            times.append((time.perf_counter() - t) * 1e3)
        times.sort()
        return times[len(times) // 2], times[0]

    def image():
        raw = fbo.read(components=3)
        return np.frombuffer(raw, dtype=np.uint8).reshape(height, width, 3)[::-1]

    return timed, image, ctx.info["GL_RENDERER"]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("glb")
    ap.add_argument("--width", type=int, default=1280)
    ap.add_argument("--height", type=int, default=720)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--repeat", type=int, default=30)
    ap.add_argument("--rounds", type=int, default=3,
                    help="alternate the two renderers this many times and keep each one's best median "
                         "(two-thread timings on small machines vary from run to run)")
    ap.add_argument("--method", default="zbuffer")
    ap.add_argument("--msaa", type=int, default=0, help="llvmpipe's samples per pixel (0: no MSAA)")
    ap.add_argument("--gl-filter", default="nearest", choices=["nearest", "nearest-mip", "trilinear"],
                    help="llvmpipe's texture filter")
    ap.add_argument("--aa", help="our --aa (default: our default)")
    ap.add_argument("--filter", help="our --filter (default: our default)")
    ap.add_argument("--mip", help="our --mip (default: our default)")
    ap.add_argument("--binary", default=os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "target", "release", "scanline-racer"))
    ap.add_argument("--json", action="store_true", help="print one JSON object instead of a line")
    ap.add_argument("--save", metavar="PREFIX", help="also write PREFIX-llvmpipe.png and PREFIX-ours.png")
    a = ap.parse_args()
    ensure([("numpy", "numpy"), ("moderngl", "moderngl"), ("PIL", "pillow")])
    import numpy as np
    from PIL import Image
    timed, image, renderer = llvmpipe(a.glb, a.width, a.height, a.threads, a.msaa, a.gl_filter)
    extra = []
    for flag in ("aa", "filter", "mip"):
        if getattr(a, flag):
            extra += ["--" + flag, getattr(a, flag)]
    ours_runs, theirs_runs = [], []
    with tempfile.TemporaryDirectory() as tmp:
        ours_png = os.path.join(tmp, "ours.png")
        for _ in range(max(1, a.rounds)):
            out = subprocess.run([a.binary, "render", a.glb, "--camera", "frame camera", "--width", str(a.width),
                                  "--height", str(a.height), "--threads", str(a.threads), "--repeat", str(a.repeat),
                                  "--method", a.method, "--stats", "json", "--out", ours_png] + extra,
                                 capture_output=True, text=True)
            if out.returncode != 0:
                sys.exit("scanline-racer failed: " + out.stderr.strip())
            stats = json.loads(out.stdout)
            ours_runs.append((stats["ms_median"], stats["ms_min"]))
            theirs_runs.append(timed(a.repeat))
        ours = np.asarray(Image.open(ours_png).convert("RGB")).astype(np.int16)
        if a.save:
            Image.open(ours_png).save(a.save + "-ours.png")
    img = image()
    if a.save:
        Image.fromarray(img).save(a.save + "-llvmpipe.png")
    ms, ms_min = min(theirs_runs)
    ours_ms, ours_min = min(ours_runs)
    per_round = [t[0] / o[0] for o, t in zip(ours_runs, theirs_runs)]
    match = float((np.abs(img.astype(np.int16) - ours).max(axis=2) <= 8).mean())
    r = {"width": a.width, "height": a.height, "threads": a.threads, "method": a.method, "rounds": len(ours_runs),
         "msaa": a.msaa, "gl_filter": a.gl_filter, "ours_flags": " ".join(extra),
         "llvmpipe_ms": round(ms, 3), "llvmpipe_ms_min": round(ms_min, 3),
         "ours_ms": round(ours_ms, 3), "ours_ms_min": round(ours_min, 3),
         "speedup": round(ms / ours_ms, 2), "speedup_per_round": [round(x, 2) for x in per_round],
         "pixels_matching": round(match, 4), "triangles": stats["polygons_in"], "llvmpipe": renderer}
    if a.json:
        print(json.dumps(r))
    else:
        print("%dx%d, %d thread(s): llvmpipe (msaa %d, %s) %.2f ms (best %.2f), scanline-racer %s %s %.2f ms "
              "(best %.2f): %.2fx (rounds: %s); %.2f%% of pixels match"
              % (a.width, a.height, a.threads, a.msaa, a.gl_filter, ms, ms_min, a.method, " ".join(extra), ours_ms,
                 ours_min, r["speedup"],
                 " ".join("%.2fx" % x for x in per_round), match * 100))


if __name__ == "__main__":
    main()
