#!/usr/bin/env python3
"""Writes small glTF scenes into this folder, each built around a known failure of painter's-algorithm
visibility (polygons sorted by depth, or dropped into depth buckets of an ordering table, then drawn far
to near). A correct renderer (a z-buffer, or a sort that splits polygons) draws them all right.

Run from anywhere: python3 tests/failures/make_failure_scenes.py  (deterministic: same bytes every run).

Conventions: Y up, metres, camera looks down its local -Z. Every surface has its own saturated flat
colour (material baseColorFactor), so a visibility error shows as a colour change; all materials are
opaque and double-sided (but city-blocks', one-sided as the game's buildings). Each scene has a perspective camera node "main" (the best single view) and two
nodes "start" and "end": moving linearly from start to end (eye and look target, also stored in each
camera node's extras) is a slow move that keeps the interesting part in view.

cycle.gltf -- Three tilted planks, each passing over the next (A over B, B over C, C over A) with real
    gaps of ~0.2-0.3 m between them. No drawing order of the three polygons is right: whichever is drawn
    last covers the plank that should lie on top of it at one of the three crossings.
intersecting.gltf -- A wheel (closed 12-sided cylinder) sinking 0.1 m into the road and a 1 m box half
    sunk in it. Whole polygons are drawn in one order, so the parts below the road surface (the bottom
    of the wheel, the lower half of the box) are painted over the road instead of being cut off by it.
big-ground.gltf -- One 2000 m x 2000 m ground polygon (a square turned 45 degrees so both of its
    triangles have their centroid 50 m ahead) and ten boxes 3-150 m away. Sorted by average depth the
    ground comes after every box farther than 50 m and paints over them; sorted by farthest depth it is
    first (right), sorted by nearest depth it is last and covers everything.
decals.gltf -- Road markings lying exactly in the road's plane, a number plate and a handle exactly in
    a door's plane (each decal its own primitive, listed after its surface). Depth alone cannot order
    coplanar polygons: decals whose average depth is beyond their surface's (far dashes, the plate on the
    far half of the angled door) are drawn first and vanish; equal keys fall back to arrival order.
crossing.gltf -- The track crossing over itself: a lower road running under a bridge deck 7 m up that
    carries a second road at 90 degrees, two pillars standing on the lower road's shoulders. The
    lower road's near triangle (centroid ~10 m away) is drawn after the right pillar (25 m) and paints
    over its foot; the upper road, lying on the deck, sorts at almost the deck underside's depth and
    can be drawn after it, showing through the bridge from below.
bucket-boundary.gltf -- Two boxes touching face to face exactly 20 m ahead along the view axis (the
    camera looks straight down -Z so the shared plane's view depth is exactly 20 for the whole move).
    Coplanar faces and faces on either side of 20 m land in one bucket or in neighbouring buckets
    depending on the bucket count; inside a bucket arrival order decides, and the back box is listed
    after the front box, so a coarse table paints the back box over the front one.
near-plane.gltf -- Ground and a wall running from behind the camera to far ahead, and a box whose
    front face is 0.05 m ahead (inside the 0.1 m near distance) so part of the view is inside the box.
    Polygons reaching behind the camera get sort keys near zero (drawn last: the ground's near
    triangle paints over the foot of the wall and of the marker box 6 m ahead) and must be clipped at
    the near plane, not projected through the eye.
tunnel.gltf -- The street course's tunnel: a road into a tunnel whose walls and ceiling are single long
    polygons reaching from 5 m behind the camera to 60 m ahead, the left wall 2.3 m from the eye, a car
    ahead by the left wall and a sign hanging from the ceiling. Clipped at the near plane, the walls'
    and the ceiling's nearest depth is the near distance: sorted by nearest depth they come last and
    paint over the car and the sign; by average or farthest depth they come first, as they should.
city-blocks.gltf -- The street course's occluders: a street between two rows of buildings, taller blocks
    behind them, a tower rising over the far end and a cross street, the long facades along the street
    reaching from beside the camera to far ahead. One-sided materials, as the game's buildings have. Most of what lies in the view is hidden (the z-buffer
    rejects more pixels than it keeps); a painter's order must still get every facade in front of the
    blocks behind it.
viaduct.gltf -- The mountain course's long sight line: a viaduct's deck 40 m up across a valley on
    tall piers that stand a metre into the valley's sloping sides, the valley's ground in 60 m polygons
    rising both ways from its floor, and 300 flat trees on the slopes from 300 m to 1.8 km away (the far
    plane at 3 km). Seen from a slope under the deck: the long deck's polygons span the piers' depths, the
    piers cut into ground polygons larger than themselves, and at a kilometre a depth bucket holds many
    trees that overlap each other.
slivers.gltf -- A fan of 40 triangles under 0.02 m wide (about a pixel) meeting at one point, and a
    grid of quads with T-junctions (a vertex in the middle of a neighbour's edge but not one of its
    vertices), all in one plane 10 m ahead with nothing behind. Not an ordering failure but the
    rasterisation that every painter's method depends on: any crack or dropped sliver shows background.
"""
import colorsys, math, os, sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(os.path.dirname(HERE), "scenes"))
sys.dont_write_bytecode = True  # leave no __pycache__ in tests/scenes
import make_test_scenes as mts  # noqa: E402  (Builder, look_at_matrix, data_uri)

look_at_matrix = mts.look_at_matrix
data_uri = mts.data_uri

YFOV, ZNEAR, ZFAR = 0.9, 0.1, 500.0


class Builder(mts.Builder):
    """The test-scene Builder, writing into this folder, with a few helpers for flat-coloured solids."""

    def __init__(self):
        super().__init__()
        self.g["asset"]["generator"] = "make_failure_scenes.py"
        self.mats = {}

    def write(self, name):
        # os.path.join drops the base folder when given an absolute path, so the parent writes here.
        super().write(os.path.join(HERE, name))

    def mat(self, color):
        """An opaque material of this colour, one per distinct colour: double-sided, unless the scene asked
        for one-sided materials (`self.one_sided`, as the game's buildings are)."""
        key = tuple(color)
        if key not in self.mats:
            self.mats[key] = self.material(color=key, double=not getattr(self, "one_sided", False))
        return self.mats[key]

    def cameras(self, main, start, end, zfar=ZFAR):
        """Camera nodes main, start and end, each (eye, target), seeing as far as zfar."""
        self.g["cameras"] = [{"type": "perspective", "name": "lens",
                              "perspective": {"yfov": YFOV, "znear": ZNEAR, "zfar": zfar}}]
        for name, (eye, target) in (("main", main), ("start", start), ("end", end)):
            self.node(name=name, camera=0, matrix=look_at_matrix(eye, target),
                      extras={"eye": list(eye), "target": list(target)})

    def finish(self, name):
        self.g["scenes"][0]["nodes"] = list(range(len(self.g["nodes"])))
        self.write(name)


def rgb(h, s=1.0, v=1.0):
    return tuple(round(c, 4) for c in colorsys.hsv_to_rgb(h % 1.0, s, v)) + (1.0,)


def quad(p, mat):
    """One primitive: quad p0 p1 p2 p3 (counter-clockwise seen from its front)."""
    return {"pos": [tuple(v) for v in p], "idx": [0, 1, 2, 0, 2, 3], "mat": mat}


def quads(qs, mat):
    """One primitive holding several quads."""
    pos, idx = [], []
    for q in qs:
        n = len(pos)
        pos += [tuple(v) for v in q]
        idx += [n, n + 1, n + 2, n, n + 2, n + 3]
    return {"pos": pos, "idx": idx, "mat": mat}


FACES = ("+x", "-x", "+y", "-y", "+z", "-z")


def box_faces(lo, hi):
    """The six outward-facing (counter-clockwise from outside) quads of an axis-aligned box, by FACES name."""
    out = {}
    for axis in range(3):
        for s in (1, -1):
            q = []
            for (a, c) in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
                u = [0, 0, 0]
                u[axis] = s; u[(axis + 1) % 3] = a * s; u[(axis + 2) % 3] = c
                q.append(tuple(hi[i] if u[i] > 0 else lo[i] for i in range(3)))
            out[("+" if s > 0 else "-") + "xyz"[axis]] = q
    return out


def box(b, lo, hi, colors):
    """Primitives of a box; colors is one colour or a dict FACES name -> colour (one primitive per colour)."""
    faces = box_faces(lo, hi)
    if not isinstance(colors, dict):
        colors = {f: colors for f in FACES}
    order = []
    for f in FACES:
        if colors[f] not in order:
            order.append(colors[f])
    return [quads([faces[f] for f in FACES if colors[f] == c], b.mat(c)) for c in order]


def shades(h):
    """Six saturated shades of one hue for the six faces of a box (top brightest)."""
    return {"+y": rgb(h, 1, 1.0), "+z": rgb(h, 1, 0.85), "+x": rgb(h, 1, 0.7),
            "-x": rgb(h, 0.75, 0.6), "-z": rgb(h, 0.75, 0.45), "-y": rgb(h, 0.75, 0.3)}


def yrot(deg):
    a = math.radians(deg) / 2
    return [0.0, round(math.sin(a), 7), 0.0, round(math.cos(a), 7)]


def cycle():
    b = Builder()
    side, length, half_w, h0, rise = 2.4, 4.0, 0.3, 1.0, 0.3
    rc = side / math.sqrt(3)
    corners = [(rc * math.cos(math.radians(90 + 120 * i)), rc * math.sin(math.radians(90 + 120 * i))) for i in range(3)]
    ext = (length - side) / 2
    planks = []
    for i in range(3):
        (ax, az), (bx, bz) = corners[i], corners[(i + 1) % 3]
        ux, uz = (bx - ax) / side, (bz - az) / side
        wx, wz = -uz * half_w, ux * half_w
        # Height rises along the plank: low where it passes under plank i-1, high where it passes over i+1.
        def at(t, sgn):
            return (round(ax + ux * t + sgn * wx, 5), round(h0 + rise * t / side, 5), round(az + uz * t + sgn * wz, 5))
        planks.append([at(-ext, -1), at(side + ext, -1), at(side + ext, 1), at(-ext, 1)])
    ground = quad([(-6, 0, 6), (6, 0, 6), (6, 0, -6), (-6, 0, -6)], b.mat(rgb(0.08, 0.8, 0.55)))
    b.node(name="ground", mesh=b.mesh([ground]))
    for name, p, h in zip("ABC", planks, (0.0, 0.33, 0.66)):
        b.node(name="plank " + name, mesh=b.mesh([quad(p, b.mat(rgb(h)))]))
    b.cameras(main=((0.0, 4.5, 3.8), (0.0, 1.1, 0.0)),
              start=((-0.8, 4.6, 3.6), (-0.5, 1.1, 0.0)),
              end=((0.8, 4.3, 4.0), (0.5, 1.1, 0.0)))
    b.finish("cycle.gltf")


def intersecting():
    b = Builder()
    road = quad([(-5, 0, 5), (5, 0, 5), (5, 0, -25), (-5, 0, -25)], b.mat(rgb(0, 0, 0.5)))
    b.node(name="road", mesh=b.mesh([road]))
    n, r, hw = 12, 0.35, 0.125
    ring = [(r * math.sin(-math.pi / 2 + 2 * math.pi * k / n), r * math.cos(-math.pi / 2 + 2 * math.pi * k / n)) for k in range(n)]
    ring = [(round(y, 6), round(z, 6)) for y, z in ring]
    tread = quads([[(hw, ring[k][0], ring[k][1]), (hw, ring[(k + 1) % n][0], ring[(k + 1) % n][1]),
                    (-hw, ring[(k + 1) % n][0], ring[(k + 1) % n][1]), (-hw, ring[k][0], ring[k][1])]
                   for k in range(n)], b.mat(rgb(0, 0, 0.15)))
    caps = []
    for s, col in ((1, rgb(0.78, 1, 0.4)), (-1, rgb(0.45, 1, 0.35))):
        pos = [(s * hw, 0.0, 0.0)] + [(s * hw, y, z) for y, z in ring]
        idx = [i for k in range(n) for i in ((0, 1 + (k + 1) % n, 1 + k) if s > 0 else (0, 1 + k, 1 + (k + 1) % n))]
        caps.append({"pos": pos, "idx": idx, "mat": b.mat(col)})
    # Axis along local x; centre 0.25 m up so the lowest tread vertex is 0.1 m under the road.
    b.node(name="wheel", mesh=b.mesh([tread] + caps), translation=[0.6, r - 0.1, -3.0], rotation=yrot(15))
    b.node(name="box", mesh=b.mesh(box(b, (-0.5, -0.5, -0.5), (0.5, 0.5, 0.5), shades(0.15))),
           translation=[-1.3, 0.0, -3.6], rotation=yrot(30))
    b.cameras(main=((0.0, 1.5, 1.8), (-0.3, 0.2, -3.3)),
              start=((-0.8, 1.5, 2.0), (-0.9, 0.2, -3.3)),
              end=((0.8, 1.4, 1.4), (0.4, 0.2, -3.3)))
    b.finish("intersecting.gltf")


def big_ground():
    b = Builder()
    # A 2000 m square turned 45 degrees about Y: its split diagonal runs along the view axis, so both
    # triangles (and the quad) have their average depth at the centre, 50 m ahead of the main camera.
    half_diag, zc = round(1000 * math.sqrt(2), 4), -50.0
    ground = quad([(0, 0, zc + half_diag), (half_diag, 0, zc), (0, 0, zc - half_diag), (-half_diag, 0, zc)],
                  b.mat(rgb(0.33, 1, 0.55)))
    b.node(name="ground", mesh=b.mesh([ground]))
    boxes = [(3, 12, 0.8), (6, -14, 0.5), (10, 10, 0.7), (16, -8, 1.0), (25, 6, 1.2),
             (40, -5, 1.4), (60, 4, 1.6), (85, -3, 1.8), (115, 2, 2.0), (150, -1.5, 2.0)]
    for i, (d, deg, s) in enumerate(boxes):
        x, z = round(d * math.sin(math.radians(deg)), 3), round(-d * math.cos(math.radians(deg)), 3)
        col = rgb((0.0, 0.08, 0.15, 0.5, 0.58, 0.66, 0.75, 0.83, 0.91, 0.45)[i], 1, 0.9)
        b.node(name="box %d m" % d, mesh=b.mesh(box(b, (x - s / 2, 0.0, z - s / 2), (x + s / 2, s, z + s / 2), col)))
    b.cameras(main=((0.0, 1.7, 0.0), (0.0, 1.7, -100.0)),
              start=((-1.0, 1.7, 1.0), (-3.0, 1.7, -100.0)),
              end=((1.0, 1.7, -1.0), (3.0, 1.7, -100.0)))
    b.finish("big-ground.gltf")


def decals():
    b = Builder()
    white = b.mat((1.0, 1.0, 1.0, 1.0))
    road = quad([(-4, 0, 6), (4, 0, 6), (4, 0, -40), (-4, 0, -40)], b.mat(rgb(0, 0, 0.4)))
    dashes = quads([[(-0.075, 0, z0), (0.075, 0, z0), (0.075, 0, z0 - 3), (-0.075, 0, z0 - 3)]
                    for z0 in range(2, -38, -6)], white)
    edges = quads([[(x0, 0, 6), (x0 + 0.15, 0, 6), (x0 + 0.15, 0, -40), (x0, 0, -40)] for x0 in (-3.85, 3.7)], white)
    b.node(name="road", mesh=b.mesh([road, dashes, edges]))
    # Door in its local z = 0 plane; turned so its local +x runs away from the camera.
    door = quad([(0, 0.3, 0), (1.2, 0.3, 0), (1.2, 1.3, 0), (0, 1.3, 0)], b.mat(rgb(0.0)))
    plate = quad([(0.62, 0.42, 0), (1.14, 0.42, 0), (1.14, 0.58, 0), (0.62, 0.58, 0)], b.mat(rgb(0.15)))
    handle = quad([(0.1, 0.95, 0), (0.35, 0.95, 0), (0.35, 1.03, 0), (0.1, 1.03, 0)], b.mat(rgb(0.62)))
    b.node(name="door", mesh=b.mesh([door, plate, handle]), translation=[1.8, 0.0, -2.0], rotation=yrot(35))
    b.cameras(main=((-1.0, 1.6, 5.0), (0.8, 0.2, -5.0)),
              start=((-1.8, 1.6, 5.5), (0.4, 0.2, -5.0)),
              end=((0.0, 1.5, 4.0), (1.2, 0.2, -5.0)))
    b.finish("decals.gltf")


def crossing():
    b = Builder()
    lower = quad([(-4, 0, 10), (4, 0, 10), (4, 0, -50), (-4, 0, -50)], b.mat(rgb(0, 0, 0.45)))
    b.node(name="lower road", mesh=b.mesh([lower]))
    deck = {"+y": rgb(0.75, 1, 0.9), "-y": rgb(0.75, 1, 0.55), "+z": rgb(0.85, 1, 0.8),
            "-z": rgb(0.85, 1, 0.6), "+x": rgb(0.7, 1, 0.7), "-x": rgb(0.7, 1, 0.7)}
    b.node(name="deck", mesh=b.mesh(box(b, (-30, 6.5, -29.5), (30, 7.0, -20.5), deck)))
    upper = quad([(-30, 7, -21), (30, 7, -21), (30, 7, -29), (-30, 7, -29)], b.mat(rgb(0.55, 1, 0.8)))
    b.node(name="upper road", mesh=b.mesh([upper]))
    for name, x0, h in (("left pillar", -3.8, 0.1), ("right pillar", 2.8, 0.3)):
        cols = {f: rgb(h, 1, 0.9) for f in FACES}
        cols["+z"] = rgb(h, 1, 0.65)
        b.node(name=name, mesh=b.mesh(box(b, (x0, 0, -25.5), (x0 + 1.0, 6.5, -24.5), cols)))
    b.cameras(main=((0.0, 2.5, 0.0), (0.0, 3.0, -25.0)),
              start=((-1.5, 2.5, 3.0), (-0.5, 3.0, -25.0)),
              end=((1.5, 2.5, -1.0), (0.5, 3.0, -25.0)))
    b.finish("crossing.gltf")


def bucket_boundary():
    b = Builder()
    ground = quad([(-15, 0, -2), (15, 0, -2), (15, 0, -92), (-15, 0, -92)], b.mat(rgb(0.33, 1, 0.5)))
    b.node(name="ground", mesh=b.mesh([ground]))
    # Front box z -20..-19, back box z -22..-20: the touching plane is z = -20, exactly 20 m ahead.
    b.node(name="front box", mesh=b.mesh(box(b, (-0.5, 0, -20), (0.5, 1, -19), shades(0.0))))
    b.node(name="back box", mesh=b.mesh(box(b, (-1, 0, -22), (1, 2, -20), shades(0.6))))
    # Eye and target move together, so the view axis stays exactly -Z.
    b.cameras(main=((0.0, 1.5, 0.0), (0.0, 1.5, -20.0)),
              start=((-1.5, 1.5, 0.0), (-1.5, 1.5, -20.0)),
              end=((1.5, 1.5, 0.0), (1.5, 1.5, -20.0)))
    b.finish("bucket-boundary.gltf")


def near_plane():
    b = Builder()
    # Split along the near-right to far-left diagonal: the near-left triangle's centroid is 1.7 m ahead.
    ground = quad([(15, 0, 15), (15, 0, -35), (-15, 0, -35), (-15, 0, 15)], b.mat(rgb(0.33, 1, 0.5)))
    b.node(name="ground", mesh=b.mesh([ground]))
    wall = quad([(-1, 0, 4), (-1, 0, -15), (-1, 2.5, -15), (-1, 2.5, 4)], b.mat(rgb(0.08)))
    b.node(name="wall", mesh=b.mesh([wall]))
    b.node(name="far marker", mesh=b.mesh(box(b, (-0.6, 0, -6.5), (-0.1, 1.5, -6), rgb(0.55, 1, 0.9))))
    # The eye is at (0, 1, 0): the box's front face is 0.05 m ahead, inside the 0.1 m near distance, and
    # the box covers the lower right of the near-plane rectangle, so that part of the view is inside it.
    b.node(name="box at the eye", mesh=b.mesh(box(b, (0.0, 0.25, -1.5), (1.2, 1.03, -0.05), shades(0.8))))
    b.cameras(main=((0.0, 1.0, 0.0), (0.0, 1.0, -10.0)),
              start=((-0.02, 1.0, 0.02), (-0.6, 0.95, -10.0)),
              end=((0.01, 1.0, -0.02), (0.6, 1.0, -10.0)))
    b.finish("near-plane.gltf")


def tunnel():
    b = Builder()
    road = quad([(-2.5, 0, 5), (6.5, 0, 5), (6.5, 0, -60), (-2.5, 0, -60)], b.mat(rgb(0, 0, 0.4)))
    b.node(name="road", mesh=b.mesh([road]))
    left = quad([(-2.3, 0, 5), (-2.3, 0, -60), (-2.3, 5, -60), (-2.3, 5, 5)], b.mat(rgb(0.1, 0.6, 0.7)))
    right = quad([(6.3, 0, -60), (6.3, 0, 5), (6.3, 5, 5), (6.3, 5, -60)], b.mat(rgb(0.15, 0.6, 0.6)))
    ceiling = quad([(-2.3, 5, 5), (-2.3, 5, -60), (6.3, 5, -60), (6.3, 5, 5)], b.mat(rgb(0.05, 0.5, 0.5)))
    b.node(name="walls", mesh=b.mesh([left, right]))
    b.node(name="ceiling", mesh=b.mesh([ceiling]))
    b.node(name="car by the wall", mesh=b.mesh(box(b, (-2.2, 0, -13), (-0.4, 1.3, -9), shades(0.0))))
    b.node(name="sign", mesh=b.mesh(box(b, (-1.5, 3.6, -20.3), (4.5, 4.99, -20), shades(0.6))))
    b.node(name="exit", mesh=b.mesh(box(b, (-2.3, 0, -61), (6.3, 5, -60), rgb(0.55, 0.3, 1.0))))
    b.cameras(main=((0.0, 1.2, 0.0), (0.0, 1.5, -20.0)),
              start=((0.2, 1.2, 2.0), (0.0, 1.5, -20.0)),
              end=((-0.2, 1.2, -2.0), (0.2, 1.5, -20.0)))
    b.finish("tunnel.gltf")


def city_blocks():
    b = Builder()
    b.one_sided = True  # as the game's buildings: a box's inner faces are culled, never drawn
    road = quad([(-6, 0, 5), (6, 0, 5), (6, 0, -200), (-6, 0, -200)], b.mat(rgb(0, 0, 0.4)))
    cross = quad([(-80, 0.0, -70), (80, 0.0, -70), (80, 0.0, -82), (-80, 0.0, -82)], b.mat(rgb(0, 0, 0.35)))
    b.node(name="street", mesh=b.mesh([road]))
    b.node(name="cross street", mesh=b.mesh([cross]))
    k = 0
    for side in (-1, 1):
        # The front row: long blocks from beside the camera to the cross street, and on past it.
        for (z0, z1, h) in ((8, -30, 18), (-30, -70, 26), (-82, -130, 22), (-130, -200, 30)):
            x0, x1 = (8, 24) if side > 0 else (-24, -8)
            b.node(name=f"front {k}", mesh=b.mesh(box(b, (x0, 0, z1), (x1, h, z0), shades(0.07 * k))))
            k += 1
        # The row behind, taller, hidden but for what rises over the front row.
        for (z0, z1, h) in ((0, -40, 34), (-40, -68, 44), (-84, -150, 40)):
            x0, x1 = (30, 50) if side > 0 else (-50, -30)
            b.node(name=f"behind {k}", mesh=b.mesh(box(b, (x0, 0, z1), (x1, h, z0), shades(0.07 * k))))
            k += 1
    b.node(name="tower", mesh=b.mesh(box(b, (-15, 0, -240), (15, 120, -210), shades(0.5))))
    b.cameras(main=((2.0, 1.5, 0.0), (0.0, 4.0, -60.0)),
              start=((3.0, 1.5, 3.0), (0.0, 4.0, -60.0)),
              end=((-2.0, 1.5, -3.0), (0.0, 4.0, -60.0)))
    b.finish("city-blocks.gltf")


def viaduct():
    b = Builder()
    ground_y = lambda x: 0.25 * abs(x) - 40.0
    tiles = []
    for z0 in range(140, -1900, -60):
        for x0 in range(-480, 480, 60):
            x1, z1 = x0 + 60, z0 - 60
            tiles.append(((x0, ground_y(x0), z0), (x1, ground_y(x1), z0), (x1, ground_y(x1), z1), (x0, ground_y(x0), z1)))
    for k in range(2):
        b.node(name=f"valley {k}", mesh=b.mesh([quads(tiles[k::2], b.mat(rgb(0.3 + 0.05 * k, 0.8, 0.7)))]))
    b.node(name="deck", mesh=b.mesh(box(b, (-400, -1.5, -126), (400, 0.0, -114), shades(0.08))))
    b.node(name="parapets", mesh=b.mesh(box(b, (-400, 0.0, -126), (400, 1.0, -125.6), rgb(0.6, 0.5, 1.0))
                                           + box(b, (-400, 0.0, -114.4), (400, 1.0, -114), rgb(0.62, 0.5, 1.0))))
    for k, x in enumerate(range(-360, 361, 40)):
        foot = ground_y(x) - 1.0
        if foot < -1.5:
            b.node(name=f"pier {k}", mesh=b.mesh(box(b, (x - 1.1, foot, -121.6), (x + 1.1, -1.5, -118.4),
                                                       shades(0.9 + 0.013 * k))))
    seed = 12345
    trees = []
    for k in range(300):
        seed = (seed * 1103515245 + 12345) % (1 << 31)
        z = -300.0 - 1500.0 * (seed / (1 << 31))
        seed = (seed * 1103515245 + 12345) % (1 << 31)
        x = (seed / (1 << 31)) * 900.0 - 450.0
        y = ground_y(x) - 0.3
        trees.append(((x - 4, y, z), (x + 4, y, z), (x + 4, y + 12, z), (x - 4, y + 12, z)))
    for k in range(3):
        b.node(name=f"trees {k}", mesh=b.mesh([quads(trees[k::3], b.mat(rgb(0.15 + 0.1 * k, 1.0, 0.5)))]))
    b.cameras(main=((-60.0, -23.0, 60.0), (30.0, -8.0, -300.0)),
              start=((-70.0, -25.0, 70.0), (20.0, -8.0, -300.0)),
              end=((-50.0, -20.0, 50.0), (40.0, -6.0, -300.0)), zfar=3000.0)
    b.finish("viaduct.gltf")


def slivers():
    b = Builder()
    z = -10.0
    # Fan: 40 triangles, 0.0196 m wide at their 4 m rim, meeting at the apex; even and odd ones in two
    # primitives with identical shared positions.
    apex, radius, n, dphi = (-3.0, 4.2), 4.0, 40, 0.0049
    rim = [(round(apex[0] + radius * math.sin(-n * dphi / 2 + k * dphi), 6),
            round(apex[1] - radius * math.cos(-n * dphi / 2 + k * dphi), 6)) for k in range(n + 1)]
    pos = [(apex[0], apex[1], z)] + [(x, y, z) for x, y in rim]
    fan = [{"pos": pos, "idx": [i for k in range(parity, n, 2) for i in (0, 1 + k, 2 + k)], "mat": b.mat(col)}
           for parity, col in ((0, rgb(0.08)), (1, rgb(0.6)))]
    b.node(name="fan", mesh=b.mesh(fan))
    # Grid of 1.5 m cells from (-1.5, 0.5), 4 x 2; cells split into halves or quarters leave T-junctions
    # on the edges of their unsplit neighbours (all coordinates exact in binary).
    x0, y0, e = -1.5, 0.5, 1.5
    layout = {(0, 0): "whole", (1, 0): "h", (2, 0): "whole", (3, 0): "quarters",
              (0, 1): "v", (1, 1): "whole", (2, 1): "h", (3, 1): "whole"}
    rects = []
    for r in range(2):
        for c in range(4):
            ax, ay, h = x0 + c * e, y0 + r * e, e / 2
            kind = layout[(c, r)]
            if kind == "whole":
                rects.append((ax, ay, e, e))
            elif kind == "h":
                rects += [(ax, ay, e, h), (ax, ay + h, e, h)]
            elif kind == "v":
                rects += [(ax, ay, h, e), (ax + h, ay, h, e)]
            else:
                rects += [(ax + dx, ay + dy, h, h) for dy in (0, h) for dx in (0, h)]
    prims = [quad([(x, y, z), (x + w, y, z), (x + w, y + h, z), (x, y + h, z)], b.mat(rgb(0.03 + i * 0.618034)))
             for i, (x, y, w, h) in enumerate(rects)]
    b.node(name="t-junction grid", mesh=b.mesh(prims))
    b.cameras(main=((0.5, 2.2, 0.0), (0.5, 2.2, -10.0)),
              start=((-0.5, 2.0, 0.5), (0.0, 2.2, -10.0)),
              end=((1.5, 2.4, -0.5), (1.0, 2.2, -10.0)))
    b.finish("slivers.gltf")


if __name__ == "__main__":
    cycle()
    intersecting()
    big_ground()
    decals()
    crossing()
    bucket_boundary()
    near_plane()
    tunnel()
    city_blocks()
    viaduct()
    slivers()
