#!/usr/bin/env python3
"""Synthetic photo annotations (system D, Fondevilla et al.) made from KNOWN 3D models.

What it makes
-------------
Three surfaces of revolution built from developable patches, each drawn as exact cubic
Bezier curves in 3D:

  cylinder   an open tube, radius 80 px, height 160 px
  cone       an open truncated cone, bottom radius 90 px, top radius 55 px, height 150 px
  composite  a cylindrical neck (radius 80 px, height 90 px) on a cone that narrows
             downwards (radius 80 px at the joint, 50 px at the bottom, height 110 px):
             a tumbler-like piece with one crease circle (in the spirit of the paper's
             synthetic examples, Fig. 8)

Every circle is made of cubic Bezier arcs (k = 4/3 tan(arc/4), i.e. the standard
0.5523 for a quarter circle) and the 3D Bezier curves ARE the truth: each patch is the
ruled surface between corresponding points of its two circle curves (same joint angles
and same k on both, so the lower curve is the upper one scaled about the apex: a true
cylinder or cone, exactly developable).  The joint angles of every circle are the exact
silhouette angles (normal perpendicular to the view, solved by bisection to machine
precision) plus their mirror images about the symmetry plane, so the silhouette rulings
start and end at segment ends and the top rim is exactly mirror-symmetric.

Symmetry plane: through the axis and the world direction azimuth + 45 deg (the plane
through the axis and the view direction would be seen edge-on, a degenerate annotation).
Frame: the axis (bottom centre -> top centre) and the radius from the top centre to the
top rim in that plane; points: the pair of mirror-image top-rim nodes farthest apart in
the image, ordered so that points[1] is nearer the viewer (flip_depth = false is right).
Every circle is symmetric about this plane: the closed top rim wholly, each front arc
where its mirror image is visible too; all are listed as self-symmetric (without the
front arcs nothing fixes the lower circles' depth). The silhouettes are symmetric only
about the edge-on plane, so no pair is listed.
true_size: the top-rim diameter lying in the symmetry plane.

For each model, three annotation files (format: sheetform photo annotation version 1):

  <model>-ortho.json        orthographic projection of the 3D control points (exact)
  <model>-perspective.json  perspective camera (50 deg horizontal field of view, focal
                            length 514.7 px, centre of projection 514.7 px in front of the
                            object's centre, silhouettes recomputed for that camera);
                            the control points are projected, so the curves are only
                            approximately the images of the 3D curves (on purpose)
  <model>-noisy.json        the orthographic annotation with Gaussian noise, sigma = 1 px:
                            each curve node (segment end; shared by every curve through
                            it) is moved by a 2D N(0, 1 px^2) offset and its tangent
                            handles move with it and also slide N(0, 1 px^2) along the
                            tangent (so C1 joins stay exactly collinear); the straight
                            silhouettes move their ends only and keep the inner points at
                            1/3 and 2/3.  The symmetry frame and points get the same kind
                            of noise (a point that is a curve node shares its offset);
                            true_size stays on the noisy top rim (same parameters).
                            Seeds: random.Random(SEED) with SEED = 101 (cylinder),
                            102 (cone), 103 (composite).

and next to each `<name>.json` a `<name>.truth.json` with the ground truth (3D control
points of every curve, the true rulings of every patch, the symmetry plane, the true
size, the camera), and a PNG rendering of the model (<model>-ortho.png, shared by the
noisy variant, and <model>-perspective.png), 480 x 480 px, Lambert flat shading with a
z-buffer.

Benchmark (examples/photo/bench/, kept apart because a test counts the synthetic files):

  lamp       a dense drawing: foot cone widening upwards (radius 77 -> 132 px, height
             99 px), cylindrical body (radius 132 px, height 132 px), shade cone narrowing
             upwards (radius 132 -> 72 px, height 121 px); orthographic only, same camera
             and conventions; 118 control points (the 12 joint angles are the 6 silhouette
             angles and their mirror images); files lamp.json, lamp.truth.json (with a
             "benchmark" entry: control point count, front-arc lengths, ruling spacing)
             and lamp.png.  lamp.json sets analysis.ruling_spacing_px (tuned with the
             real program for about 150 kept rulings; see examples/photo/bench/README.md).

Frame convention
----------------
Model frame: X = image x (px), Y = -(image y) (px, up), Z toward the viewer (px); the
orthographic projection drops Z (image = (X, -Y)).  The object's centre is at depth
Z = 0 and projects to the image centre (240, 240).  For the perspective files the truth is
given in the same frame (the camera frame shifted so that the scale is exactly 1 at the
object's centre depth): the centre of projection is (240, -240, D) with D = f, and a
model point (X, Y, Z) is imaged at x = 240 + f (X - 240) / (D - Z),
y = 240 - f (Y + 240) / (D - Z).  World frame (used only to build the models): the
object's axis is the world z axis; the camera has elevation 30 deg and azimuth 25 deg
(plus an image roll of 10 deg for the composite).  Units: 1 px = 0.5 mm.

How to run
----------
From the repository root (standard library only):

    python3 tools/make_photo_examples.py            # writes examples/photo/synthetic/ and bench/
    python3 tools/make_photo_examples.py --only synthetic   # (or --only bench) one folder only
    python3 tools/make_photo_examples.py --check    # re-reads the files and checks them
    python3 tools/make_photo_examples.py --no-images   # JSON only (the PNGs are slow-ish)
"""

import json
import math
import os
import random
import struct
import sys
import zlib

OUT_DIR = os.path.join("examples", "photo", "synthetic")
BENCH_DIR = os.path.join("examples", "photo", "bench")
IMG_W = IMG_H = 480
CX, CY = 240.0, 240.0            # image point of the object's centre
MM_PER_PX = 0.5
ELEVATION_DEG, AZIMUTH_DEG = 30.0, 25.0
ELEVATION = math.radians(ELEVATION_DEG)
AZIMUTH = math.radians(AZIMUTH_DEG)
PHI = AZIMUTH + math.pi / 4      # the symmetry plane: through the axis and world direction PHI
FOV = math.radians(50.0)         # perspective variant: horizontal field of view
FOCAL = (IMG_W / 2) / math.tan(FOV / 2)
NOISE_SIGMA = 1.0
MAX_ARC = 2 * math.pi / 3        # longest Bezier arc (longer gaps are split evenly)
RULINGS_PER_PATCH = 20

MODELS = [
    {"name": "cylinder", "title": "synthetic open cylinder (tube)", "seed": 101, "roll": 0.0,
     "rings": [("bottom", 0.0, 80.0), ("top", 160.0, 80.0)],
     "patches": [("tube", 0, 1)]},
    {"name": "cone", "title": "synthetic open truncated cone", "seed": 102, "roll": 0.0,
     "rings": [("bottom", 0.0, 90.0), ("top", 150.0, 55.0)],
     "patches": [("cone", 0, 1)]},
    {"name": "composite", "title": "synthetic cylinder on a cone (one crease circle)", "seed": 103,
     "roll": math.radians(10.0),
     "rings": [("bottom", 0.0, 50.0), ("joint", 110.0, 80.0), ("top", 200.0, 80.0)],
     "patches": [("cone", 0, 1), ("neck", 1, 2)]},
]

# Benchmark model(s), written to BENCH_DIR: orthographic only, files named after the model.
# The lamp's order of patches (lower cone widening upwards, cylinder, upper cone narrowing
# upwards) makes each joint circle's front arc that of the wider-fronted patch ABOVE it,
# so no annotated curve is hidden (a cone narrowing upwards BELOW a thinner cylinder, or
# a cone widening upwards ON a cylinder, would hide part of the joint circle and of the
# lower silhouettes behind the upper patch and make false 2D crossings).
BENCH_MODELS = [
    {"name": "lamp", "title": "benchmark lamp: foot cone, cylindrical body, shade cone (dense drawing)",
     "roll": 0.0, "single": True,
     "rings": [("bottom", 0.0, 77.0), ("foot-top", 99.0, 132.0), ("body-top", 231.0, 132.0),
               ("top", 352.0, 72.0)],
     "patches": [("foot", 0, 1), ("body", 1, 2), ("shade", 2, 3)],
     "colours": {"foot": (120, 120, 130), "body": (205, 140, 80), "shade": (235, 215, 150)},
     # spacing of the kept rulings (px), tuned with the real program; see bench_stats() and examples/photo/bench/README.md
     "ruling_spacing_px": 4.6,
     "target_rulings": 150},
]


# ----------------------------------------------------------------------------- vectors
def add(a, b): return [x + y for x, y in zip(a, b)]
def sub(a, b): return [x - y for x, y in zip(a, b)]
def mul(a, s): return [x * s for x in a]
def dot(a, b): return sum(x * y for x, y in zip(a, b))
def norm(a): return math.sqrt(dot(a, a))
def unit(a): return mul(a, 1.0 / norm(a))
def cross(a, b): return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
def cross2(a, b): return a[0] * b[1] - a[1] * b[0]


def bez(p, t):
    s = 1.0 - t
    return [s * s * s * a + 3 * s * s * t * b + 3 * s * t * t * c + t * t * t * d for a, b, c, d in zip(*p)]


def bez_d(p, t):
    s = 1.0 - t
    return [3 * s * s * (b - a) + 6 * s * t * (c - b) + 3 * t * t * (d - c) for a, b, c, d in zip(*p)]


def curve_point(points, u):
    """Point at global parameter u = segment + t of a piecewise cubic (list of points)."""
    k = (len(points) - 1) // 3
    j = min(int(math.floor(u)), k - 1)
    return bez(points[3 * j:3 * j + 4], u - j)


# ----------------------------------------------------------------------------- camera
class Camera:
    def __init__(self, roll, zmid, perspective):
        ce, se, ca, sa = math.cos(ELEVATION), math.sin(ELEVATION), math.cos(AZIMUTH), math.sin(AZIMUTH)
        x = [-sa, ca, 0.0]
        y = [-se * ca, -se * sa, ce]
        self.z = [ce * ca, ce * sa, se]                  # toward the viewer
        self.roll = roll
        cr, sr = math.cos(roll), math.sin(roll)
        self.x = add(mul(x, cr), mul(y, sr))
        self.y = add(mul(x, -sr), mul(y, cr))
        self.centre = [0.0, 0.0, zmid]                   # world point imaged at (CX, CY), depth 0
        self.perspective = perspective
        self.f = FOCAL
        self.d = FOCAL                                   # scale 1 at the centre's depth
        self.eye_world = add(self.centre, mul(self.z, self.d))

    def model(self, w):
        v = sub(w, self.centre)
        return [dot(self.x, v) + CX, dot(self.y, v) - CY, dot(self.z, v)]

    def image_of_model(self, m):
        if not self.perspective:
            return [m[0], -m[1]]
        s = self.f / (self.d - m[2])
        return [CX + s * (m[0] - CX), CY - s * (m[1] + CY)]

    def image(self, w):
        return self.image_of_model(self.model(w))

    def facing(self, w, n):
        """> 0 where the outward normal n at world point w faces the camera."""
        if self.perspective:
            return dot(n, sub(self.eye_world, w))
        return dot(n, self.z)

    def describe(self):
        d = {"type": "perspective" if self.perspective else "orthographic",
             "elevation_deg": ELEVATION_DEG, "azimuth_deg": AZIMUTH_DEG,
             "roll_deg": round(math.degrees(self.roll), 9),
             "world_to_model": {
                 "note": "model = [x_axis.(w - world_centre) + 240, y_axis.(w - world_centre) - 240, z_axis.(w - world_centre)]; world z = the object's axis",
                 "x_axis": self.x, "y_axis": self.y, "z_axis": self.z, "world_centre": self.centre}}
        if self.perspective:
            d.update({"focal_px": self.f, "horizontal_fov_deg": round(math.degrees(FOV), 9),
                      "principal_point_px": [CX, CY],
                      "centre_of_projection_model": [CX, -CY, self.d],
                      "projection": "x = 240 + f (X - 240) / (D - Z), y = 240 - f (Y + 240) / (D - Z), D = f (scale 1 at depth Z = 0, the object's centre)"})
        else:
            d["projection"] = "x = X, y = -Y"
        return d


# ----------------------------------------------------------------------------- geometry
def ring_pt(ring, th):
    _, z, r = ring
    return [r * math.cos(th), r * math.sin(th), z]


def patch_normal(lo, hi, th):
    """Outward normal of the patch between rings lo and hi (world) along the ruling at th."""
    dz, dr = hi[1] - lo[1], hi[2] - lo[2]
    return [math.cos(th) * dz, math.sin(th) * dz, -dr]


def arc_bezier(ring, a, b):
    """Cubic Bezier control points (world) of the arc from angle a to b > a on the ring."""
    _, z, r = ring
    k = 4.0 / 3.0 * math.tan((b - a) / 4.0)
    p0, p3 = ring_pt(ring, a), ring_pt(ring, b)
    p1 = add(p0, [-k * r * math.sin(a), k * r * math.cos(a), 0.0])
    p2 = sub(p3, [-k * r * math.sin(b), k * r * math.cos(b), 0.0])
    return [p0, p1, p2, p3]


BASE = AZIMUTH - math.pi    # angles are kept in [BASE, BASE + 2 pi): the front (around AZIMUTH) never wraps


def normang(t):
    return BASE + (t - BASE) % (2 * math.pi)


def silhouette_angles(cam, lo, hi):
    """The two angles where the patch's normal is perpendicular to the view (ray), and the
    front interval between them (th1 < th2, facing > 0 inside)."""
    def g(th):
        return cam.facing(ring_pt(lo, th), patch_normal(lo, hi, th))
    n = 7200
    ths = [BASE + 2 * math.pi * i / n for i in range(n + 1)]
    vals = [g(t) for t in ths]
    roots = []
    for i in range(n):
        if (vals[i] > 0) != (vals[i + 1] > 0):
            a, b, ga = ths[i], ths[i + 1], vals[i]
            for _ in range(200):
                m = 0.5 * (a + b)
                if m <= a or m >= b:
                    break
                gm = g(m)
                if (gm > 0) == (ga > 0):
                    a, ga = m, gm
                else:
                    b = m
            roots.append(a if abs(g(a)) <= abs(g(b)) else b)
    assert len(roots) == 2, roots
    th1, th2 = sorted(roots)
    assert g(0.5 * (th1 + th2)) > 0 and th1 < AZIMUTH < th2, "the front arc must contain the azimuth"
    return th1, th2


def joint_angles(sils, max_arc=MAX_ARC):
    """Silhouette angles and their mirror images about the plane PHI, longest gaps split."""
    js = []
    for t in sils:
        for u in (t, normang(2 * PHI - t)):      # t is already in [BASE, BASE + 2 pi)
            if all(min((u - v) % (2 * math.pi), (v - u) % (2 * math.pi)) > 1e-12 for v in js):
                js.append(u)
    js.sort()
    gaps = [(js[i], js[i + 1] if i + 1 < len(js) else js[0] + 2 * math.pi) for i in range(len(js))]
    extra = []
    for a, b in gaps:
        m = int(math.ceil((b - a) / max_arc - 1e-12))
        extra += [normang(a + (b - a) * i / m) for i in range(1, m)]
    js = sorted(js + extra)
    mingap = min((js[(i + 1) % len(js)] - js[i]) % (2 * math.pi) for i in range(len(js)))
    assert mingap > math.radians(3.0), "joint angles too close: pick another symmetry plane"
    return js


class Model:
    """One model seen by one camera: its 3D curves (world and model frame) and annotation."""

    def __init__(self, spec, perspective):
        self.spec = spec
        self.rings = spec["rings"]
        zs = [r[1] for r in self.rings]
        self.cam = Camera(spec["roll"], 0.5 * (min(zs) + max(zs)), perspective)
        # silhouettes of every patch
        self.patches = []
        for pname, i, j in spec["patches"]:
            lo, hi = self.rings[i], self.rings[j]
            th1, th2 = silhouette_angles(self.cam, lo, hi)
            self.patches.append({"name": pname, "lo": i, "hi": j, "front": (th1, th2)})
        sils = [t for p in self.patches for t in p["front"]]
        self.joints = joint_angles(sils, spec.get("max_arc", MAX_ARC))
        js = self.joints
        self.arcs = [(js[i], js[i + 1] if i + 1 < len(js) else js[0] + 2 * math.pi) for i in range(len(js))]
        self.curves = []       # dicts: name, kind, closed, world (control points), arcs or ruling
        top = len(self.rings) - 1
        # rings: the top one closed, the others their visible front arcs
        for ri in range(top, -1, -1):
            ring = self.rings[ri]
            if ri == top:
                start = self.patch_of_ring(ri)[0]["front"][0]
                k0 = [i for i, (a, _) in enumerate(self.arcs) if a == start][0]
                arcs = self.arcs[k0:] + [(a + 2 * math.pi, b + 2 * math.pi) for a, b in self.arcs[:k0]]
                name, closed = "top", True
            else:
                fronts = [p["front"] for p in self.patch_of_ring(ri)]
                t1, t2 = min(f[0] for f in fronts), max(f[1] for f in fronts)
                arcs = [(a, b) for a, b in self.arcs if a >= t1 and b <= t2]
                assert arcs[0][0] == t1 and arcs[-1][1] == t2
                name, closed = ring[0] + "-front", False
            pts = []
            for a, b in arcs:
                seg = arc_bezier(ring, a, b)
                pts += seg if not pts else seg[1:]
            if closed:
                pts[-1] = pts[0]
            self.curves.append({"name": name, "kind": "boundary", "closed": closed, "world": pts,
                                "ring": ri, "arcs": arcs})
        # silhouettes: one straight cubic per silhouette ruling (upper end first)
        single = len(self.patches) == 1
        for p in reversed(self.patches):
            lo, hi = self.rings[p["lo"]], self.rings[p["hi"]]
            ends = []
            for th in p["front"]:
                ends.append((self.cam.image(ring_pt(hi, th))[0], th))
            for side, (_, th) in zip(("left", "right"), sorted(ends)):
                a, b = ring_pt(hi, th), ring_pt(lo, th)
                d = sub(b, a)
                pts = [a, add(a, mul(d, 1 / 3)), add(a, mul(d, 2 / 3)), b]
                name = f"{side}-silhouette" if single else f"{p['name']}-{side}-silhouette"
                self.curves.append({"name": name, "kind": "silhouette", "closed": False, "world": pts,
                                    "ruling": th, "patch": p["name"]})
                p[side] = th
        for c in self.curves:
            c["model"] = [self.cam.model(w) for w in c["world"]]
            c["image"] = [self.cam.image_of_model(m) for m in c["model"]]

    def patch_of_ring(self, ri):
        return [p for p in self.patches if p["lo"] == ri or p["hi"] == ri]

    def curve(self, name):
        return [c for c in self.curves if c["name"] == name][0]

    def ring_curve(self, ri):
        return [c for c in self.curves if c.get("ring") == ri][0]

    def place(self, ri, th):
        """(curve name, global parameter u) of the point at angle th on ring ri's curve.
        th must be a joint or the midpoint of an arc (both lie exactly on the circle)."""
        c = self.ring_curve(ri)
        for j, (a, b) in enumerate(c["arcs"]):
            for tt in (th, th + 2 * math.pi, th - 2 * math.pi):
                if abs(tt - a) < 1e-12:
                    return c["name"], float(j)
                if abs(tt - 0.5 * (a + b)) < 1e-12:
                    return c["name"], j + 0.5
                if abs(tt - b) < 1e-12 and j == len(c["arcs"]) - 1:
                    return c["name"], float(j + 1)
        raise ValueError("angle is not on a joint or an arc midpoint")

    def world_at(self, name, u):
        return curve_point(self.curve(name)["world"], u)

    # ------------------------------------------------------------------ symmetry + size
    def mirror_world(self, w):
        n = [-math.sin(PHI), math.cos(PHI), 0.0]
        return sub(w, mul(n, 2 * dot(n, w)))

    def annotation_marks(self):
        """World points of the symmetry frame, the symmetric pair and the true size."""
        top = len(self.rings) - 1
        ring = self.rings[top]
        zs = [r[1] for r in self.rings]
        bc, tc = [0.0, 0.0, min(zs)], [0.0, 0.0, max(zs)]
        rim_phi = self.place(top, normang(PHI))
        frame = [[bc, tc], [tc, self.world_at(*rim_phi)]]
        # mirror pair: top-rim joints (th, 2 PHI - th), the one farthest apart in the image
        best = None
        for th in self.joints:
            th2 = normang(2 * PHI - th)
            if abs(th2 - th) < 1e-9 or abs(abs(th2 - th) - 2 * math.pi) < 1e-9:
                continue
            pa, pb = self.place(top, th), self.place(top, th2)
            wa, wb = self.world_at(*pa), self.world_at(*pb)
            d = norm(sub(self.cam.image(wa), self.cam.image(wb)))
            if best is None or d > best[0]:
                if self.cam.model(wa)[2] > self.cam.model(wb)[2]:   # points[1] nearer
                    pa, pb, wa, wb = pb, pa, wb, wa
                best = (d, [pa, pb], [wa, wb])
        size = [rim_phi, self.place(top, normang(PHI + math.pi))]
        return {"frame": frame, "pair_places": best[1], "pair": best[2], "size_places": size,
                "opening": tc, "ring": ring}


# ----------------------------------------------------------------------------- noise
def add_noise(curves, rng, sigma):
    """Noisy copies of the 2D curves (list of dicts with name/kind/closed/image)."""
    nodes = {}

    def key(p):
        return (round(p[0], 6), round(p[1], 6))

    def node_offset(p):
        k = key(p)
        if k not in nodes:
            nodes[k] = [rng.gauss(0, sigma), rng.gauss(0, sigma)]
        return nodes[k]

    out = []
    for c in curves:
        pts = c["image"]
        n = len(pts)
        new = [None] * n
        for i in range(0, n, 3):
            new[i] = add(pts[i], node_offset(pts[i]))
        if c["kind"] == "silhouette":
            d = sub(new[3], new[0])
            new[1], new[2] = add(new[0], mul(d, 1 / 3)), add(new[0], mul(d, 2 / 3))
        else:
            for h in range(n):
                if h % 3 == 0:
                    continue
                o = h - 1 if h % 3 == 1 else h + 1
                v = sub(pts[h], pts[o])
                length = norm(v)
                new[h] = add(new[o], mul(v, (length + rng.gauss(0, sigma)) / length))
        if c["closed"]:
            new[-1] = list(new[0])
        out.append(new)
    return out, node_offset


# ----------------------------------------------------------------------------- files
def build(spec, variant):
    persp = variant == "perspective"
    m = Model(spec, persp)
    cam = m.cam
    marks = m.annotation_marks()
    if spec.get("single"):
        name, img_name = spec["name"], spec["name"] + ".png"
    else:
        name = f"{spec['name']}-{variant}"
        img_name = f"{spec['name']}-{'perspective' if persp else 'ortho'}.png"
    images = [c["image"] for c in m.curves]
    frame_img = [[cam.image(p) for p in seg] for seg in marks["frame"]]
    pair_img = [cam.image(w) for w in marks["pair"]]
    if variant == "noisy":
        rng = random.Random(spec["seed"])
        images, node_offset = add_noise(m.curves, rng, NOISE_SIGMA)
        frame_img = [[add(p, node_offset(p)) for p in seg] for seg in frame_img]
        pair_img = [add(p, node_offset(p)) for p in pair_img]
    by_name = {c["name"]: pts for c, pts in zip(m.curves, images)}
    size_img = [curve_point(by_name[n], u) for n, u in marks["size_places"]]
    size_world = [m.world_at(n, u) for n, u in marks["size_places"]]
    size_px = norm(sub(size_world[0], size_world[1]))
    ann = {
        "name": spec["title"] if spec.get("single") else f"{spec['title']} ({variant})",
        "image": {"path": img_name, "width": IMG_W, "height": IMG_H},
        # The camera a perspective photo was taken with (the principal point is the
        # image centre, the reader's default).
        **({"camera": {"projection": "perspective", "focal_length_px": cam.f}} if persp else {}),
        "units": "mm",
        "curves": [{"name": c["name"], "kind": c["kind"], "closed": c["closed"], "control_points": pts}
                   for c, pts in zip(m.curves, images)],
        "symmetry": {"frame": frame_img, "points": pair_img, "flip_depth": False},
        # Every circle of a surface of revolution is symmetric about a plane through the
        # axis: the closed rim wholly, the front arcs where their mirror image is visible
        # too (the reconstruction pairs only the points whose mirror it can see). Without
        # them nothing fixes the lower circles' depth.
        "self_symmetric_curves": [c["name"] for c in m.curves if c["kind"] == "boundary"],
        "openings": [cam.image(marks["opening"])],
        "true_size": {"from": size_img[0], "to": size_img[1], "length": size_px * MM_PER_PX},
    }
    if "ruling_spacing_px" in spec:
        ann["analysis"] = {"ruling_spacing_px": spec["ruling_spacing_px"]}
    # ---- truth
    mdl = cam.model
    n_world = [-math.sin(PHI), math.cos(PHI), 0.0]
    n_model = [dot(cam.x, n_world), dot(cam.y, n_world), dot(cam.z, n_world)]
    patches = []
    for p in m.patches:
        lo, hi = m.rings[p["lo"]], m.rings[p["hi"]]
        lo_c, hi_c = m.ring_curve(p["lo"]), m.ring_curve(p["hi"])
        th1, th2 = p["front"]
        front = [(a, b) for a, b in m.arcs if a >= th1 and b <= th2]
        rulings = []
        for i in range(RULINGS_PER_PATCH):
            # evenly spaced in angle: arc j and t = the fraction of its angle
            th = th1 + (th2 - th1) * i / (RULINGS_PER_PATCH - 1)
            j = max(k for k, (a, _) in enumerate(front) if a <= th or k == 0)
            a, b = front[j]
            t = min(1.0, max(0.0, (th - a) / (b - a)))
            if i == RULINGS_PER_PATCH - 1:
                t = 1.0
            ends = []
            for ring, c in ((hi, hi_c), (lo, lo_c)):
                w = bez(arc_bezier(ring, a, b), t)
                jj = [k for k, (aa, bb) in enumerate(c["arcs"]) if abs(aa - a) < 1e-12 or abs(aa - a - 2 * math.pi) < 1e-12][0]
                ends.append((c["name"], jj + t, w))
            rulings.append({
                "image": [cam.image(e[2]) for e in ends],
                "model": [mdl(e[2]) for e in ends],
                "on_curves": [[e[0], e[1]] for e in ends],
                "silhouette": i in (0, RULINGS_PER_PATCH - 1)})
        kind = "cylinder" if lo[2] == hi[2] else "cone"
        entry = {"name": p["name"], "type": kind,
                 "lower_circle": {"centre_model": mdl([0, 0, lo[1]]), "radius_px": lo[2]},
                 "upper_circle": {"centre_model": mdl([0, 0, hi[1]]), "radius_px": hi[2]},
                 "axis_direction_model": unit(sub(mdl([0, 0, hi[1]]), mdl([0, 0, lo[1]]))),
                 "silhouette_angles_deg": [math.degrees(th1), math.degrees(th2)],
                 "silhouette_curves": [c["name"] for c in m.curves if c.get("patch") == p["name"]],
                 "visible_rulings": rulings}
        if kind == "cone":
            zap = lo[1] + (hi[1] - lo[1]) * lo[2] / (lo[2] - hi[2])
            entry["apex_model"] = mdl([0, 0, zap])
        patches.append(entry)
    frame_desc = ("model frame: X = image x (px), Y = -(image y) (px, up), Z toward the viewer (px); "
                  "orthographic projection drops Z; the object's centre is at depth Z = 0")
    if persp:
        frame_desc = ("camera frame before projection, shifted and scaled so that it matches the image "
                      "exactly at the object's centre depth: X = image x, Y = -(image y) at depth Z = 0, "
                      "Z toward the camera (px); centre of projection (240, -240, f), f = %.6f px "
                      "(50 deg horizontal field of view); x = 240 + f (X - 240)/(f - Z), y = 240 - f (Y + 240)/(f - Z). "
                      "The annotation's curves are the perspective images of the 3D CONTROL POINTS, so they "
                      "are only approximately the images of the 3D curves." % FOCAL)
    truth = {
        "annotation": name + ".json",
        "frame": frame_desc,
        "camera": cam.describe(),
        "units": "mm", "mm_per_px": MM_PER_PX,
        "surface": ("each patch is the ruled surface between corresponding points (same segment, same t) "
                    "of its lower and upper circle curves; its rulings are straight lines"),
        "curves": {c["name"]: {"kind": c["kind"], "closed": c["closed"],
                               "control_points_model": c["model"]} for c in m.curves},
        "patches": patches,
        "symmetry": {
            "plane_normal_model": n_model, "plane_point_model": mdl([0, 0, 0]),
            "plane": "through the axis and the world direction azimuth + 45 deg (not seen edge-on)",
            "frame_model": [[mdl(p) for p in seg] for seg in marks["frame"]],
            "points_model": [mdl(w) for w in marks["pair"]],
            "points_on_curve": [[n, u] for n, u in marks["pair_places"]],
            "depth": "points[1] is nearer the viewer (larger Z): flip_depth = false is the true interpretation",
            "symmetric_curve_pairs": [],
            "self_symmetric_curves": [c["name"] for c in m.curves if c["kind"] == "boundary"]},
        "true_size": {"from_model": mdl(size_world[0]), "to_model": mdl(size_world[1]),
                      "on_curve": [[n, u] for n, u in marks["size_places"]],
                      "length_px": size_px, "length_mm": size_px * MM_PER_PX},
    }
    if variant == "noisy":
        truth["noise"] = {"sigma_px": NOISE_SIGMA, "seed": spec["seed"],
                          "note": "the truth is the noise-free orthographic model"}
    if "target_rulings" in spec:
        truth["benchmark"] = bench_stats(spec, m, ann)
    return name, img_name, ann, truth, m


def bench_stats(spec, m, ann):
    """Control point count and the ruling spacing estimate of a benchmark model."""
    per_patch = []
    for p in m.patches:
        th1, th2 = p["front"]
        front = [(a, b) for a, b in m.arcs if a >= th1 and b <= th2]
        lengths = []
        for ri in (p["lo"], p["hi"]):
            ring, length = m.rings[ri], 0.0
            for a, b in front:
                seg = [m.cam.image(w) for w in arc_bezier(ring, a, b)]
                pts = [bez(seg, i / 200) for i in range(201)]
                length += sum(norm(sub(q, r)) for q, r in zip(pts, pts[1:]))
            lengths.append(length)
        per_patch.append({"patch": p["name"], "front_arc_lengths_px": lengths,
                          "mean_px": 0.5 * (lengths[0] + lengths[1])})
    total = sum(x["mean_px"] for x in per_patch)
    return {
        "annotated_control_points": sum(len(c["control_points"]) for c in ann["curves"]),
        "segments_per_curve": {c["name"]: (len(c["control_points"]) - 1) // 3 for c in ann["curves"]},
        "front_arcs": per_patch,
        "front_arc_length_sum_px": total,
        "target_rulings": spec["target_rulings"],
        "ruling_spacing_estimate_px": total / spec["target_rulings"],
        "ruling_spacing_px": spec["ruling_spacing_px"],
        "note": ("the reconstruction keeps a ruling once the mean arc length along the two curves it "
                 "joins has grown by ruling_spacing_px since the last kept one, stepping along a warping "
                 "path whose steps are one sample spacing (default image diagonal / 250 = 2.715 px) long: "
                 "the kept spacing is rounded up to whole steps, so front_arc_length_sum_px / "
                 "target_rulings (ruling_spacing_estimate_px) is only a guide; ruling_spacing_px was "
                 "tuned with the real program (149 rulings for 4.1 ... 5.0 px)"),
    }


# ----------------------------------------------------------------------------- image
def render(m, path, ss=2):
    cam = m.cam
    W, H = IMG_W * ss, IMG_H * ss
    zbuf = [[-1e30] * W for _ in range(H)]
    bg = (226, 226, 226)
    col = [[bg] * W for _ in range(H)]
    light = unit([-0.35, 0.45, 0.8])
    colours = {"tube": (205, 140, 80), "cone": (205, 140, 80), "neck": (90, 150, 205)}
    colours.update(m.spec.get("colours", {}))
    tris = []
    for p in m.patches:
        lo, hi = m.rings[p["lo"]], m.rings[p["hi"]]
        steps = 24
        strip = []
        for a, b in m.arcs:
            blo, bhi = arc_bezier(lo, a, b), arc_bezier(hi, a, b)
            for s in range(steps):
                t = s / steps
                strip.append((bez(blo, t), bez(bhi, t)))
        strip.append(strip[0])
        for (l0, h0), (l1, h1) in zip(strip, strip[1:]):
            q = [cam.model(w) for w in (l0, l1, h1, h0)]
            wn = cross(sub(l1, l0), sub(h0, l0))
            if dot(wn, [l0[0] + l1[0], l0[1] + l1[1], 0]) < 0:
                wn = mul(wn, -1)                          # outward
            nm = unit([dot(cam.x, wn), dot(cam.y, wn), dot(cam.z, wn)])
            mid = mul(add(add(l0, l1), add(h0, h1)), 0.25)
            front = cam.facing(mid, wn) > 0
            base = colours[p["name"]]
            if front:
                shade = 0.4 + 0.6 * max(0.0, dot(nm, light))
            else:
                base = tuple(int(0.6 * c) for c in base)
                shade = 0.35 + 0.45 * max(0.0, -dot(nm, light))
            c = tuple(min(255, int(round(v * shade))) for v in base)
            sp = [[v * ss for v in cam.image_of_model(x)] + [x[2]] for x in q]
            tris.append((sp[0], sp[1], sp[2], c))
            tris.append((sp[0], sp[2], sp[3], c))
    for a, b, c, colour in tris:
        area = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
        if abs(area) < 1e-12:
            continue
        x0, x1 = max(0, int(min(a[0], b[0], c[0]))), min(W - 1, int(max(a[0], b[0], c[0])) + 1)
        y0, y1 = max(0, int(min(a[1], b[1], c[1]))), min(H - 1, int(max(a[1], b[1], c[1])) + 1)
        inv = 1.0 / area
        for y in range(y0, y1 + 1):
            py = y + 0.5
            zr, cr = zbuf[y], col[y]
            for x in range(x0, x1 + 1):
                px = x + 0.5
                w0 = ((b[0] - px) * (c[1] - py) - (b[1] - py) * (c[0] - px)) * inv
                w1 = ((c[0] - px) * (a[1] - py) - (c[1] - py) * (a[0] - px)) * inv
                w2 = 1.0 - w0 - w1
                if w0 < -1e-9 or w1 < -1e-9 or w2 < -1e-9:
                    continue
                z = w0 * a[2] + w1 * b[2] + w2 * c[2]
                if z > zr[x]:
                    zr[x] = z
                    cr[x] = colour
    rows = []
    for y in range(IMG_H):
        row = bytearray(b"\x00")
        for x in range(IMG_W):
            acc = [0, 0, 0]
            for dy in range(ss):
                for dx in range(ss):
                    px = col[y * ss + dy][x * ss + dx]
                    acc[0] += px[0]; acc[1] += px[1]; acc[2] += px[2]
            row += bytes(int(round(v / (ss * ss))) for v in acc)
        rows.append(bytes(row))
    write_png(path, IMG_W, IMG_H, b"".join(rows))


def write_png(path, w, h, raw):
    def chunk(t, d):
        return struct.pack(">I", len(d)) + t + d + struct.pack(">I", zlib.crc32(t + d) & 0xffffffff)
    data = (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
            + chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))
    with open(path, "wb") as f:
        f.write(data)


def png_size(path):
    with open(path, "rb") as f:
        head = f.read(24)
    assert head[:8] == b"\x89PNG\r\n\x1a\n" and head[12:16] == b"IHDR"
    return struct.unpack(">II", head[16:24])


README = """# Synthetic photo annotations (generated)

Ground-truth test inputs for the photo reconstruction (system D, Fondevilla et al.,
"Patterns from Photograph"). **Generated** by `tools/make_photo_examples.py`; do not edit
by hand, re-run `python3 tools/make_photo_examples.py` from the repository root
(`--check` re-reads and checks them).

Models (each made of exact cubic Bezier curves in 3D; every patch is the ruled surface
between its two circle curves):

- `cylinder-*`: an open tube, radius 80 px, height 160 px.
- `cone-*`: an open truncated cone, radii 90 px (bottom) and 55 px (top), height 150 px.
- `composite-*`: a cylindrical neck (radius 80 px, height 90 px) on a cone narrowing
  downwards to radius 50 px (height 110 px); image rolled by 10 deg.

Variants:

- `*-ortho.json`: orthographic projection of the 3D control points (exact).
- `*-perspective.json`: perspective camera (50 deg horizontal field of view, f = 514.7 px,
  scale 1 at the object's centre depth), given to the reconstruction in the annotation's
  `camera` (`focal_length_px`); silhouettes are those of that camera; the
  projected control points make the curves only approximately the images of the 3D curves.
- `*-noisy.json`: the orthographic annotation with Gaussian noise (sigma 1 px, fixed
  seeds) on the control points, keeping C1 joins collinear and silhouettes straight.
  It uses the `*-ortho.png` image.
- `*.truth.json`: the ground truth for the annotation of the same name: 3D control points
  of every curve, about 20 true rulings per patch (image and 3D end points), the symmetry
  plane, the true size and the camera.
- `*.png`: 480 x 480 px renderings (flat Lambert shading) the annotations refer to.

Frame convention of the truth files: model frame X = image x (px), Y = -(image y) (px, up),
Z toward the viewer (px); orthographic projection drops Z. 1 px = 0.5 mm; `true_size` is a
top-rim diameter in mm. For the perspective files the truth is in the camera frame shifted
and scaled to match the image at the object's centre depth (see each file's `frame`).

Symmetry plane: through the axis at 45 deg from the viewing direction's horizontal part
(so not seen edge-on). Every circle is self-symmetric about it: the closed top rim
wholly, each front arc where its mirror image is visible too (listed in
`self_symmetric_curves`: without them nothing fixes the lower circles' depth). No pair
of curves is mirror-symmetric about it.

Licence: made by the sheetform project; same licence as the project (MIT OR Apache-2.0).
"""


BENCH_README = """# Benchmark photo annotation (generated)

A dense synthetic annotation for timing the photo reconstruction (system D, Fondevilla
et al.) on a drawing with many control points and rulings. **Generated** by
`tools/make_photo_examples.py` (`--only bench` writes only this folder; `--check` re-reads
and checks it); do not edit by hand. It is kept out of `../synthetic/`, whose file count
the tests rely on.

- `lamp.json`: a lamp made of three coaxial developable patches, drawn under the same
  orthographic 3/4 view as the synthetic models (elevation 30 deg, azimuth 25 deg; the
  control points are the exact projections of the 3D cubic Bezier control points):
  a foot cone widening upwards (radius 77 -> 132 px, height 99 px), a cylindrical body
  (radius 132 px, height 132 px) and a shade cone narrowing upwards (radius 132 -> 72 px,
  height 121 px). Curves: the closed top rim (12 cubic arcs), the front arcs of the two
  joint circles (8 and 6 arcs) and of the bottom circle (4 arcs), and two straight
  silhouettes per patch: 118 control points in all. The arcs' ends are every patch's
  silhouette angles and their mirror images about the symmetry plane. An opening in the
  top rim; symmetry plane, frame, points, `self_symmetric_curves` (every circle) and
  `true_size` (a top-rim diameter, mm) as in the synthetic models.
  `analysis.ruling_spacing_px` = 4.6 px: the reconstruction keeps 149 rulings in all
  (3 strips). The front arcs bounding the patches are 814.9 px long in all (sum over the
  patches of the mean image length of a patch's two front arcs), i.e. 5.43 px per ruling
  for 150 rulings; but the kept rulings are picked from the warping path, whose steps are
  one sample spacing (default image diagonal / 250 = 2.715 px) long, so the kept spacing
  is about two samples (5.4 px) for any `ruling_spacing_px` from about 4.1 to 5.0 px
  (149 rulings; 182 at 2.8 - 3.5 px, 163 at 4.0 px, 140 - 145 at 5.05 - 5.3 px, 113 at
  5.45 px). 4.6 px is the middle of that plateau.
- `lamp.truth.json`: the ground truth (3D control points, 20 true rulings per patch,
  symmetry plane, true size, camera), as in `../synthetic/`, plus a `benchmark` entry with
  the control point count and the front-arc lengths.
- `lamp.png`: 480 x 480 px rendering (flat Lambert shading).

Why this order of patches: each joint circle's visible (front) arc must be that of the
patch above it. A cone narrowing upwards under a thinner cylinder, or a cone widening
upwards on a cylinder, would hide part of the joint circle and of the lower silhouettes
behind the upper patch, and the drawn hidden lines would cross visible ones.

Frame convention, units (1 px = 0.5 mm) and symmetry conventions: see
`../synthetic/README.md`.

Licence: made by the sheetform project; same licence as the project (MIT OR Apache-2.0).
"""


def dumps(obj, indent=0):
    """JSON with every list of numbers (a point) on one line."""
    pad, pad1 = " " * indent, " " * (indent + 1)
    if isinstance(obj, list) and all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in obj):
        return json.dumps(obj)
    if isinstance(obj, list):
        if not obj:
            return "[]"
        return "[\n" + ",\n".join(pad1 + dumps(v, indent + 1) for v in obj) + "\n" + pad + "]"
    if isinstance(obj, dict):
        return "{\n" + ",\n".join(pad1 + json.dumps(k) + ": " + dumps(v, indent + 1) for k, v in obj.items()) + "\n" + pad + "}"
    return json.dumps(obj)


def groups(which):
    """(folder, models, variants, README text) of the selected groups."""
    out = []
    if which in ("all", "synthetic"):
        out.append((OUT_DIR, MODELS, ("ortho", "perspective", "noisy"), README))
    if which in ("all", "bench"):
        out.append((BENCH_DIR, BENCH_MODELS, ("ortho",), BENCH_README))
    return out


def file_stem(spec, variant):
    return spec["name"] if spec.get("single") else f"{spec['name']}-{variant}"


def generate(images=True, which="all"):
    for out_dir, models, variants, readme in groups(which):
        os.makedirs(out_dir, exist_ok=True)
        for spec in models:
            for variant in variants:
                name, img_name, ann, truth, m = build(spec, variant)
                for fname, obj in ((name + ".json", ann), (name + ".truth.json", truth)):
                    with open(os.path.join(out_dir, fname), "w") as f:
                        f.write(dumps(obj) + "\n")
                if images and variant != "noisy":
                    render(m, os.path.join(out_dir, img_name))
                print("wrote", os.path.join(out_dir, name + ".json"))
                if "benchmark" in truth:
                    b = truth["benchmark"]
                    print(f"  {b['annotated_control_points']} control points; front arcs {b['front_arc_length_sum_px']:.1f} px "
                          f"-> ruling spacing estimate {b['ruling_spacing_estimate_px']:.3f} px for {b['target_rulings']} "
                          f"rulings (set: {b['ruling_spacing_px']} px)")
        with open(os.path.join(out_dir, "README.md"), "w") as f:
            f.write(readme)


# ----------------------------------------------------------------------------- checks
def dist_to_curve(p, pts):
    """Distance from 2D point p to a piecewise cubic (dense sampling + golden refinement)."""
    k = (len(pts) - 1) // 3
    best = (1e30, 0.0)
    n = 200
    for j in range(k):
        seg = pts[3 * j:3 * j + 4]
        for i in range(n + 1):
            d = norm(sub(bez(seg, i / n), p))
            if d < best[0]:
                best = (d, j + i / n)
    lo, hi = max(0.0, best[1] - 1.0 / n), min(float(k), best[1] + 1.0 / n)
    for _ in range(100):
        m1, m2 = lo + (hi - lo) / 3, hi - (hi - lo) / 3
        if norm(sub(curve_point(pts, m1), p)) < norm(sub(curve_point(pts, m2), p)):
            hi = m2
        else:
            lo = m1
    return min(best[0], norm(sub(curve_point(pts, 0.5 * (lo + hi)), p)))


def angle_deg(a, b):
    c = abs(dot(a, b)) / (norm(a) * norm(b))
    s = norm(cross(a, b)) / (norm(a) * norm(b)) if len(a) == 3 else abs(cross2(a, b)) / (norm(a) * norm(b))
    return math.degrees(math.atan2(s, c))


def check(which="all"):
    ok = True

    def fail(msg):
        nonlocal ok
        ok = False
        print("  FAIL:", msg)

    cases = [(out_dir, spec, variant) for out_dir, models, variants, _ in groups(which)
             for spec in models for variant in variants]
    for out_dir, spec, variant in cases:
            name = file_stem(spec, variant)
            exact = variant == "ortho"
            ann = json.load(open(os.path.join(out_dir, name + ".json")))
            tru = json.load(open(os.path.join(out_dir, name + ".truth.json")))
            print(f"{name}:")
            w, h = png_size(os.path.join(out_dir, ann["image"]["path"]))
            if (w, h) != (ann["image"]["width"], ann["image"]["height"]):
                fail("image size")
            curves = {c["name"]: c for c in ann["curves"]}
            worst_c1, worst_straight, worst_proj = 0.0, 0.0, 0.0
            for c in ann["curves"]:
                p = c["control_points"]
                if len(p) < 4 or (len(p) - 1) % 3:
                    fail(f"{c['name']}: {len(p)} points")
                for q in p:
                    if not (0 <= q[0] <= w and 0 <= q[1] <= h):
                        fail(f"{c['name']}: point outside the image")
                joins = list(range(3, len(p) - 1, 3))
                if c["closed"]:
                    if p[-1] != p[0]:
                        fail(f"{c['name']}: closed but ends differ")
                    joins.append(0)
                for j in joins:
                    a, b = sub(p[j], p[j - 1 if j else len(p) - 2]), sub(p[j + 1], p[j])
                    s = cross2(a, b) / (norm(a) * norm(b))
                    worst_c1 = max(worst_c1, abs(s))
                    if dot(a, b) <= 0:
                        fail(f"{c['name']}: cusp at {j}")
                if c["kind"] == "silhouette":
                    d = sub(p[3], p[0])
                    for q in p[1:3]:
                        worst_straight = max(worst_straight, abs(cross2(d, sub(q, p[0]))) / dot(d, d))
                t3 = tru["curves"][c["name"]]["control_points_model"]
                if exact:
                    worst_proj = max(worst_proj, max(norm(sub(q, [m[0], -m[1]])) for q, m in zip(p, t3)))
            print(f"  C1 joins: max |sin| = {worst_c1:.2e}; silhouettes: max deviation/len = {worst_straight:.2e}"
                  + (f"; |annotation - projected truth| max = {worst_proj:.2e} px" if exact else ""))
            if worst_c1 > 1e-9:
                fail("C1 joins not collinear to 1e-9")
            if worst_straight > 1e-9:
                fail("silhouette not straight")
            if exact and worst_proj > 1e-9:
                fail("annotation is not the projection of the truth")
            # every curve end touches another curve
            worst_end = 0.0
            for c in ann["curves"]:
                if c["closed"]:
                    continue
                for e in (c["control_points"][0], c["control_points"][-1]):
                    d = min(dist_to_curve(e, o["control_points"]) for o in ann["curves"] if o is not c)
                    worst_end = max(worst_end, d)
            print(f"  curve ends: farthest from another curve = {worst_end:.2e} px")
            if worst_end > 1e-9:
                fail("a curve end does not touch another curve")
            # true size / symmetric points on curves
            ts = ann["true_size"]
            dts = max(min(dist_to_curve(q, c["control_points"]) for c in ann["curves"]) for q in (ts["from"], ts["to"]))
            dsp = max(min(dist_to_curve(q, c["control_points"]) for c in ann["curves"]) for q in ann["symmetry"]["points"])
            t = tru["true_size"]
            l3 = norm(sub(t["from_model"], t["to_model"])) * tru["mm_per_px"]
            print(f"  true_size: {ts['length']:.6f} mm (truth {l3:.6f}), ends {dts:.1e} px from a curve; "
                  f"symmetric points {dsp:.1e} px from a curve")
            if dts > 1e-9 or dsp > 1e-9 or abs(l3 - ts["length"]) > 1e-9:
                fail("true_size / symmetric points")
            # symmetry annotation
            (a0, a1), (b0, b1) = ann["symmetry"]["frame"]
            ub, vb = sub(a1, a0), sub(b1, b0)
            sb = sub(ann["symmetry"]["points"][1], ann["symmetry"]["points"][0])
            sz2 = -dot(ub, sb) * dot(vb, sb) / dot(ub, vb)
            frame_angle = angle_deg(ub, vb)
            nt = tru["symmetry"]["plane_normal_model"]
            if sz2 <= 0:
                fail(f"s_z^2 = {sz2}")
                err = float("nan")
            else:
                nrec = unit([sb[0], -sb[1], math.sqrt(sz2)])
                err = angle_deg(nrec, nt)
                pm = tru["symmetry"]["points_model"]
                sign_ok = (pm[1][2] - pm[0][2]) > 0
                if not sign_ok:
                    fail("points[1] is not the nearer one")
            print(f"  symmetry: frame image angle {frame_angle:.2f} deg, s_z^2 = {sz2:.3f} px^2, "
                  f"recovered normal off the true one by {err:.3e} deg")
            if exact and not err < 1e-9:
                fail("recovered normal")
            # mirror symmetry of the listed curves, in 3D
            n = nt
            p0 = tru["symmetry"]["plane_point_model"]

            def mirror(q):
                return sub(q, mul(n, 2 * dot(n, sub(q, p0))))

            def same(a, b, closed):
                cands = [b, b[::-1]]
                if closed:
                    core = b[:-1]
                    cands = []
                    for s in range(0, len(core), 3):
                        r = core[s:] + core[:s]
                        r = r + [r[0]]
                        cands += [r, r[::-1]]
                return min(max(norm(sub(x, y)) for x, y in zip(a, c)) for c in cands if len(c) == len(a))

            pairs = [(x, x) for x in ann.get("self_symmetric_curves", [])] + [tuple(x) for x in ann.get("symmetric_curves", [])]
            for x, y in pairs:
                cx_, cy_ = tru["curves"][x], tru["curves"][y]
                if x == y and not cx_["closed"]:
                    # A front arc of a circle centred on the plane's axis: symmetric where
                    # its mirror image is visible, by construction.
                    continue
                d = same([mirror(q) for q in cx_["control_points_model"]], cy_["control_points_model"], cx_["closed"])
                print(f"  mirror({x}) vs {y}: max control point distance {d:.2e} px")
                if d > 1e-9:
                    fail(f"{x}/{y} not mirror-symmetric")
            # the mirror plane really is one of the frame / pair
            fm = tru["symmetry"]["frame_model"]
            dev = max(abs(dot(n, sub(q, p0))) for seg in fm for q in seg)
            pm = tru["symmetry"]["points_model"]
            dev = max(dev, norm(sub(mirror(pm[0]), pm[1])))
            u3, v3 = sub(fm[0][1], fm[0][0]), sub(fm[1][1], fm[1][0])
            print(f"  frame in plane / pair mirrored: {dev:.1e} px; frame 3D angle {math.degrees(math.acos(dot(u3, v3) / norm(u3) / norm(v3))):.12f} deg")
            # rulings: silhouettes are normal-perpendicular-to-view, rulings end on the curves
            worst_sil, worst_on = 0.0, 0.0
            for p in tru["patches"]:
                for r in p["visible_rulings"]:
                    for (cn, u), q in zip(r["on_curves"], r["image"]):
                        if exact:
                            worst_on = max(worst_on, norm(sub(curve_point(curves[cn]["control_points"], u), q)))
                    if r["silhouette"]:
                        a, b = r["model"]
                        cn, u = r["on_curves"][0]
                        c3 = tru["curves"][cn]["control_points_model"]
                        j = min(int(math.floor(u)), (len(c3) - 1) // 3 - 1)
                        tan = bez_d(c3[3 * j:3 * j + 4], u - j)
                        nn = unit(cross(sub(b, a), tan))
                        if variant == "perspective":
                            eye = [CX, -CY, FOCAL]
                            view = unit(sub(eye, a))
                        else:
                            view = [0, 0, 1]
                        worst_sil = max(worst_sil, abs(dot(nn, view)))
            print(f"  silhouette rulings: max |n.view| = {worst_sil:.1e}" +
                  (f"; ruling ends off the annotated curves by {worst_on:.1e} px" if exact else ""))
            if worst_sil > 1e-6 or worst_on > 1e-9:
                fail("rulings")
    print("ALL CHECKS PASSED" if ok else "SOME CHECKS FAILED")
    return ok


def parse_which(argv):
    """--only synthetic | --only bench (default: both)."""
    which = "all"
    for i, a in enumerate(argv):
        if a.startswith("--only"):
            v = a.split("=", 1)[1] if "=" in a else (argv[i + 1] if i + 1 < len(argv) else "")
            if v not in ("synthetic", "bench"):
                sys.exit("--only takes synthetic or bench")
            which = v
    return which


if __name__ == "__main__":
    which = parse_which(sys.argv[1:])
    if "--check" in sys.argv:
        sys.exit(0 if check(which) else 1)
    generate(images="--no-images" not in sys.argv, which=which)
