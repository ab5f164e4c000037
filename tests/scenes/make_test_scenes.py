#!/usr/bin/env python3
"""Writes the hand-made glTF test scenes in this folder (deterministic: same bytes every run).

Run from anywhere: python3 tests/scenes/make_test_scenes.py
"""
import base64, json, math, os, struct, zlib

HERE = os.path.dirname(os.path.abspath(__file__))


def png(w, h, rgba_rows):
    raw = b"".join(b"\x00" + bytes(row) for row in rgba_rows)
    def chunk(t, d):
        c = struct.pack(">I", len(d)) + t + d
        return c + struct.pack(">I", zlib.crc32(t + d) & 0xFFFFFFFF)
    ihdr = struct.pack(">IIBBBBB", w, h, 8, 6, 0, 0, 0)
    return b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b"")


def data_uri(mime, data):
    return "data:%s;base64,%s" % (mime, base64.b64encode(data).decode())


class Builder:
    def __init__(self):
        self.buf = bytearray()
        self.g = {"asset": {"version": "2.0", "generator": "make_test_scenes.py"},
                  "scenes": [{"nodes": []}], "scene": 0, "nodes": [], "meshes": [], "accessors": [],
                  "bufferViews": [], "materials": [], "textures": [], "images": [], "samplers": [], "cameras": []}

    def view(self, data, target=None):
        while len(self.buf) % 4:
            self.buf.append(0)
        v = {"buffer": 0, "byteOffset": len(self.buf), "byteLength": len(data)}
        if target:
            v["target"] = target
        self.buf += data
        self.g["bufferViews"].append(v)
        return len(self.g["bufferViews"]) - 1

    def accessor(self, values, kind, comps):
        flat = [c for v in values for c in (v if isinstance(v, (list, tuple)) else [v])]
        if kind == "idx":
            data = struct.pack("<%dH" % len(flat), *flat)
            acc = {"bufferView": self.view(data, 34963), "componentType": 5123, "count": len(flat), "type": "SCALAR"}
        else:
            data = struct.pack("<%df" % len(flat), *flat)
            acc = {"bufferView": self.view(data, 34962), "componentType": 5126, "count": len(values),
                   "type": {1: "SCALAR", 2: "VEC2", 3: "VEC3", 4: "VEC4"}[comps]}
            if comps == 3:
                acc["min"] = [min(v[i] for v in values) for i in range(3)]
                acc["max"] = [max(v[i] for v in values) for i in range(3)]
        self.g["accessors"].append(acc)
        return len(self.g["accessors"]) - 1

    def texture(self, w, h, rows, wrap_s=10497, wrap_t=10497):
        self.g["images"].append({"uri": data_uri("image/png", png(w, h, rows))})
        self.g["samplers"].append({"wrapS": wrap_s, "wrapT": wrap_t, "magFilter": 9728, "minFilter": 9728})
        self.g["textures"].append({"source": len(self.g["images"]) - 1, "sampler": len(self.g["samplers"]) - 1})
        return len(self.g["textures"]) - 1

    def material(self, color=(1, 1, 1, 1), tex=None, double=False, mask=None):
        m = {"pbrMetallicRoughness": {"baseColorFactor": list(color)}, "doubleSided": double}
        if tex is not None:
            m["pbrMetallicRoughness"]["baseColorTexture"] = {"index": tex}
        if mask is not None:
            m["alphaMode"] = "MASK"
            m["alphaCutoff"] = mask
        self.g["materials"].append(m)
        return len(self.g["materials"]) - 1

    def mesh(self, prims):
        out = []
        for p in prims:
            attrs = {"POSITION": self.accessor(p["pos"], "f", 3)}
            if "uv" in p:
                attrs["TEXCOORD_0"] = self.accessor(p["uv"], "f", 2)
            if "col" in p:
                attrs["COLOR_0"] = self.accessor(p["col"], "f", len(p["col"][0]))
            prim = {"attributes": attrs, "material": p["mat"], "mode": p.get("mode", 4)}
            if "idx" in p:
                prim["indices"] = self.accessor(p["idx"], "idx", 1)
            out.append(prim)
        self.g["meshes"].append({"primitives": out})
        return len(self.g["meshes"]) - 1

    def node(self, **kw):
        self.g["nodes"].append(kw)
        return len(self.g["nodes"]) - 1

    def write(self, name):
        self.g["buffers"] = [{"byteLength": len(self.buf), "uri": data_uri("application/octet-stream", bytes(self.buf))}]
        for k in [k for k, v in self.g.items() if v == []]:
            del self.g[k]
        with open(os.path.join(HERE, name), "w") as f:
            json.dump(self.g, f, indent=1, sort_keys=True)
            f.write("\n")


def checker_rows(n, a, b):
    return [[c for x in range(n) for c in (a if (x + y) % 2 == 0 else b)] for y in range(n)]


def look_at_matrix(eye, target):
    f = [t - e for t, e in zip(target, eye)]
    l = math.sqrt(sum(c * c for c in f)); f = [c / l for c in f]
    r = [f[1] * 0 - f[2] * 1, f[2] * 0 - f[0] * 0, f[0] * 1 - f[1] * 0]
    l = math.sqrt(sum(c * c for c in r)); r = [c / l for c in r]
    u = [r[1] * f[2] - r[2] * f[1], r[2] * f[0] - r[0] * f[2], r[0] * f[1] - r[1] * f[0]]
    # Column-major camera-to-world: x = right, y = up, z = -forward, translation = eye.
    return r + [0] + u + [0] + [-c for c in f] + [0] + list(eye) + [1]


def courtyard():
    b = Builder()
    ground_tex = b.texture(8, 8, checker_rows(8, (230, 230, 230, 255), (40, 90, 40, 255)))
    crate_tex = b.texture(4, 4, [[c for x in range(4) for c in ((200, 120, 40, 255) if x in (0, 3) or y in (0, 3) else (120, 70, 20, 255))] for y in range(4)], 33648, 33648)
    fence_tex = b.texture(8, 1, [[c for x in range(8) for c in ((250, 250, 250, 255) if x % 2 == 0 else (0, 0, 0, 0))]])
    m_ground = b.material(tex=ground_tex)
    m_crate = b.material(tex=crate_tex)
    m_fence = b.material(color=(0.9, 0.3, 0.2, 1), tex=fence_tex, double=True, mask=0.5)
    m_vc = b.material(double=True)
    m_wheel = b.material(color=(0.15, 0.15, 0.2, 1), double=True)
    ground = b.mesh([{"pos": [(-10, 0, 10), (10, 0, 10), (10, 0, -30), (-10, 0, -30)],
                      "uv": [(0, 8), (8, 8), (8, -8), (0, -8)], "idx": [0, 1, 2, 0, 2, 3], "mat": m_ground}])
    faces = []
    for axis in range(3):
        for s in (-1, 1):
            quad = []
            for (a, c) in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
                p = [0, 0, 0]; p[axis] = s; p[(axis + 1) % 3] = a * s; p[(axis + 2) % 3] = c
                quad.append(tuple(p))
            faces.append(quad)
    pos, uv, idx = [], [], []
    for q in faces:
        base = len(pos)
        pos += q
        uv += [(0, 0), (2, 0), (2, 2), (0, 2)]
        idx += [base, base + 1, base + 2, base, base + 2, base + 3]
    crate = b.mesh([{"pos": pos, "uv": uv, "idx": idx, "mat": m_crate}])
    fence = b.mesh([{"pos": [(-6, 0, -4), (0, 0, -6), (0, 2, -6), (-6, 2, -4)], "uv": [(0, 0), (3, 0), (3, 1), (0, 1)],
                     "idx": [0, 1, 2, 0, 2, 3], "mat": m_fence}])
    strip = b.mesh([{"pos": [(2, 0.01, -1), (2.5, 1.5, -1.5), (3.5, 0.01, -1.5), (4, 1.8, -2.5), (5, 0.01, -2.5)],
                     "col": [(1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 1, 1), (0, 0, 1)], "mode": 5, "mat": m_vc},
                    {"pos": [(-3, 0.02, 2), (-1.5, 0.02, 2.5), (-2, 0.02, 1), (-3.5, 0.02, 0.8), (-4.5, 0.02, 1.8)],
                     "col": [(1, 1, 1, 1), (1, 0, 1, 1), (0.2, 0.2, 1, 1), (0, 0, 0, 1), (1, 0.5, 0, 1)], "mode": 6, "mat": m_vc}])
    n = 12
    wheel_pos = [(5.0, 0.4, 1.0)] + [(5.0, 0.4 + 0.8 * math.sin(2 * math.pi * i / n), 1.0 + 0.8 * math.cos(2 * math.pi * i / n)) for i in range(n)]
    wheel = b.mesh([{"pos": wheel_pos, "idx": [i for k in range(n) for i in (0, 1 + k, 1 + (k + 1) % n)], "mat": m_wheel}])
    kids = [b.node(mesh=ground, name="ground"),
            b.node(mesh=crate, name="crate", translation=[1.5, 1.0, -3.0], rotation=[0, 0.3826834, 0, 0.9238795]),
            b.node(mesh=crate, name="small crate", translation=[-2.5, 0.5, -8.0], scale=[0.5, 0.5, 0.5]),
            b.node(mesh=fence, name="fence"), b.node(mesh=strip, name="strips"), b.node(mesh=wheel, name="wheel")]
    b.g["cameras"] = [{"type": "perspective", "name": "eye", "perspective": {"yfov": 0.9, "znear": 0.1, "zfar": 200.0}},
                      {"type": "orthographic", "name": "plan", "orthographic": {"xmag": 8, "ymag": 6, "znear": 0.1, "zfar": 100}}]
    cam = b.node(camera=0, name="eye cam", matrix=look_at_matrix((3.0, 3.0, 8.0), (0.0, 0.5, -3.0)))
    top = b.node(camera=1, name="top cam", translation=[0, 30, -5], rotation=[-0.7071068, 0, 0, 0.7071068])
    root = b.node(children=kids + [cam, top], name="root")
    b.g["scenes"][0]["nodes"] = [root]
    b.write("courtyard.gltf")


if __name__ == "__main__":
    courtyard()
