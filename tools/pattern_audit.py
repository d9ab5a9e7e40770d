#!/usr/bin/env python3
"""Audits a pattern as a maker gets it: from the files `sheetform` wrote, not its report.

    python3 tools/pattern_audit.py OUT_DIR [--clearance MM]

Reads OUT_DIR/model.obj (3D positions and the flat pattern as `vt`), pattern.svg (what
is printed or cut) and pattern.dxf (ezdxf), plus the pattern scale from report.json (an
input, not a result). Prints one JSON object:

- glued edge pairs: boundary edges of the flat pattern whose two copies are the same
  3D edge; for each, the tab bases (SVG layer `fold-tab`) lying on each copy:
  `pairs_tab_one`, `pairs_tab_both`, `pairs_tab_none`;
- seams: maximal runs of glued pairs consecutive on both copies (broken where the two
  copies meet, at the apex of a slit); each seam ID printed (`text.seam`) is given to the
  glued side nearest to it in its piece; `seams_id_both` have one text on each side, the
  same; `seams_id_one_side` have a text on one side only; `seams_id_mismatch` have
  different texts; `seams_id_none` none; `seam_ids_reused`: texts printed on more than
  two labels;
- `tab_depth_min_mm`: the shallowest tab drawn (the outer points of the cut path off the
  piece outlines, measured from their tab base); `tab_clearance_min_mm`: the least
  distance from a tab's outer edges to any other cut line (lines through a base corner
  measured from the tab's far end); `tabs_closer_than_clearance`;
- `zero_width_slits`: glued pairs whose two copies lie end to end on one line of one
  piece (an edge cut for nothing, its two IDs printed side by side);
- `cut_crossings`: cut segments that cross; `piece_gap_min_mm`: the least distance
  between the cut loops of different pieces; `slit_gap_min_mm` and
  `slit_pairs_closer_than_clearance`: within one loop, segments that share no point and
  come closer than the clearance (narrow slits of a net);
- `labels_over_lines`, `labels_outside`: labels whose text box meets a line or leaves
  the cut loops;
- `dxf`: the layers of the DXF's entities and whether each layer holds one kind of line
  of the SVG (`layers_apart`): cut, mountain, valley, tab score, guide, ... never mixed.

Pieces are registered onto the SVG (each may have been turned and moved by sheet
packing): every place a piece fits is found (its vertices and edges on the printed cut
loops and tab bases, no printed crease through it off its interior edges), then the
pieces are assigned to places all together, no printed vertex under two pieces
(congruent pieces fit each other's places: registered one by one, the first could take
a place only a later one fits). Geometry decides; where congruent pieces could swap
places (no printed name inside either), the cut loop's `data-mesh-pieces` (the web
editor's link from a loop to its mesh piece) breaks the tie.
"""
import json
import math
import os
import re
import sys
import xml.etree.ElementTree as ET
from collections import Counter, defaultdict

import numpy as np

SVG = "{http://www.w3.org/2000/svg}"


def read_obj(path):
    """Positions, flat positions, faces (v, vt index pairs), unit and each face's group:
    (its name, the number of `g` lines before it less one: the writer's mesh piece)."""
    v, vt, faces, unit, group, groups = [], [], [], "mm", ("", -1), []
    for line in open(path):
        if line.startswith("# units:"):
            unit = line.split()[2]
        p = line.split()
        if not p:
            continue
        if p[0] == "v":
            v.append(tuple(float(x) for x in p[1:4]))
        elif p[0] == "vt":
            vt.append((float(p[1]), float(p[2])))
        elif p[0] == "f":
            corners = [c.split("/") for c in p[1:4]]
            faces.append([(int(c[0]) - 1, int(c[1]) - 1) for c in corners])
            groups.append(group)
        elif p[0] == "g":
            group = (" ".join(p[1:]), group[1] + 1)
    return v, np.array(vt), faces, unit, groups


UNIT_MM = {"mm": 1.0, "cm": 10.0, "m": 1000.0, "in": 25.4}


def parse_svg(path):
    root = ET.parse(path).getroot()
    layers = {}
    for g in root.iter(SVG + "g"):
        if g.get("id"):
            layers[g.get("id")] = g
    view = [float(x) for x in root.get("viewBox").split()]
    loops, loop_pieces = [], []
    for p in layers["cut"].iter(SVG + "path"):
        # The mesh pieces the loop's piece holds, as the file says (`data-mesh-pieces`,
        # the web editor's too): only a tie-break between congruent pieces.
        held = p.get("data-mesh-pieces")
        held = frozenset(int(x) for x in held.split()) if held is not None else None
        for ring in p.get("d").split("Z"):
            pts = [(float(x), -float(y)) for x, y in re.findall(r"[ML]\s*([-\d.e+]+),([-\d.e+]+)", ring)]
            if pts:
                loops.append(np.array(pts))
                loop_pieces.append(held)
    lines = defaultdict(list)
    for lid, g in layers.items():
        for ln in g.findall(SVG + "line"):
            a = (float(ln.get("x1")), -float(ln.get("y1")))
            b = (float(ln.get("x2")), -float(ln.get("y2")))
            lines[lid].append((np.array(a), np.array(b)))
    texts = []
    if "labels" in layers:
        for t in layers["labels"].iter(SVG + "text"):
            x, y, size = float(t.get("x")), float(t.get("y")), float(t.get("font-size"))
            m = re.search(r"rotate\(([-\d.e+]+)", t.get("transform", ""))
            angle = -math.radians(float(m.group(1))) if m else 0.0
            texts.append({"class": t.get("class"), "text": t.text or "", "centre": np.array([x, -y]),
                          "size": size, "angle": angle})
    return view, loops, loop_pieces, lines, texts


def find(parent, x):
    """The root of `x` in the union-find forest `parent` (a list or a dict), halving
    the path on the way."""
    while parent[x] != x:
        parent[x] = parent[parent[x]]
        x = parent[x]
    return x


def point_segment_distance(p, a, b):
    d = b - a
    n = d @ d
    t = 0.0 if n == 0 else min(1.0, max(0.0, (p - a) @ d / n))
    return float(np.linalg.norm(p - (a + t * d)))


def segments_cross(a, b, c, d):
    def cross(o, p, q):
        return (p[0] - o[0]) * (q[1] - o[1]) - (p[1] - o[1]) * (q[0] - o[0])
    d1, d2 = cross(a, b, c), cross(a, b, d)
    d3, d4 = cross(c, d, a), cross(c, d, b)
    return d1 * d2 < 0 and d3 * d4 < 0


def segment_distance(a, b, c, d):
    if segments_cross(a, b, c, d):
        return 0.0
    return min(point_segment_distance(a, c, d), point_segment_distance(b, c, d),
               point_segment_distance(c, a, b), point_segment_distance(d, a, b))


class SegmentIndex:
    """Segments in a uniform grid of their bounding boxes."""

    def __init__(self, segments, cell):
        self.segments, self.cell, self.grid = segments, cell, defaultdict(list)
        for i, (a, b) in enumerate(segments):
            for key in self._keys(np.minimum(a, b), np.maximum(a, b)):
                self.grid[key].append(i)

    def _keys(self, lo, hi):
        x0, y0 = np.floor(lo / self.cell).astype(int)
        x1, y1 = np.floor(hi / self.cell).astype(int)
        if (x1 - x0 + 1) * (y1 - y0 + 1) > 4096:
            return [("big",)]
        return [(x, y) for x in range(x0, x1 + 1) for y in range(y0, y1 + 1)]

    def near(self, lo, hi):
        found = set(self.grid.get(("big",), []))
        for key in self._keys(lo, hi):
            found.update(self.grid.get(key, []))
        return found


def encode(cells):
    """One integer per grid cell (2^30 cells either way)."""
    return (cells[..., 0] + (1 << 30)) * (1 << 31) + (cells[..., 1] + (1 << 30))


class Outline:
    """The printed outline pieces are registered on: the cut loops and the tab bases (an
    edge under a tab lies on its base, and a vertex between two tabs merged into one lies
    on their bases only); their distinct vertices, each with the printed lines leaving it
    (direction and length) and the `data-mesh-pieces` of its loop (None for a tab base's
    end off the loops)."""

    CELL = 0.05

    def __init__(self, loops, loop_pieces, tab_bases):
        self.loop_segments = [(l[i], l[(i + 1) % len(l)]) for l in loops for i in range(len(l))]
        self.segments = self.loop_segments + list(tab_bases)
        self.loop_index = SegmentIndex(self.loop_segments, 10.0)
        self.index = SegmentIndex(self.segments, 10.0)
        self.points, self.mesh_pieces, self.cells = [], [], defaultdict(list)
        lines = []
        for l, held in zip(loops, loop_pieces):
            ids = [self._vertex(p, held) for p in l]
            n = len(l)
            for i in range(n):
                for j in ((i + 1) % n, (i - 1) % n):
                    d = l[j] - l[i]
                    lines.append((ids[i], math.atan2(d[1], d[0]), float(np.hypot(*d))))
        for a, b in tab_bases:
            for p, q in ((a, b), (b, a)):
                k = self._vertex(p, None)
                d = q - p
                lines.append((k, math.atan2(d[1], d[0]), float(np.hypot(*d))))
        self.points = np.array(self.points).reshape(-1, 2)
        self.line_vertex = np.array([x[0] for x in lines], dtype=np.int64)
        self.line_angle = np.array([x[1] for x in lines])
        self.line_length = np.array([x[2] for x in lines])
        # For a coarse test at 0.05 and 0.2 mm: the cells of that size holding a vertex
        # and their neighbours (a point that close to a vertex lies in one of them).
        self.coarse = {}
        for size in (0.05, 0.2):
            base = np.floor(self.points / size).astype(np.int64)
            self.coarse[size] = np.unique(np.concatenate(
                [encode(base + np.array([dx, dy])) for dx in (-1, 0, 1) for dy in (-1, 0, 1)]))

    def _vertex(self, p, held):
        """The vertex at p (within 2e-3 mm), added if new."""
        k = self.vertex_at(p, 2e-3)
        if k is None:
            k = len(self.points)
            self.points.append(p)
            self.mesh_pieces.append(held)
            self.cells[tuple(np.floor(p / self.CELL).astype(int))].append(k)
        return k

    def vertex_at(self, p, tolerance):
        """The printed vertex nearest p within the tolerance (at most CELL), or None."""
        cx, cy = np.floor(p / self.CELL).astype(int)
        best, best_d = None, tolerance
        for dx in (-1, 0, 1):
            for dy in (-1, 0, 1):
                for k in self.cells.get((cx + dx, cy + dy), ()):
                    d = float(np.linalg.norm(self.points[k] - p))
                    if d <= best_d:
                        best, best_d = k, d
        return best

    def near_vertices(self, P, size):
        """For each of the points P (… × 2): may it lie within `size` (0.05 or 0.2 mm)
        of a vertex? (True for each point that does, and for some up to twice as far.)"""
        cells, codes = self.coarse[size], encode(np.floor(P / size).astype(np.int64))
        return cells[np.minimum(np.searchsorted(cells, codes), len(cells) - 1)] == codes

    def on_loop(self, p, tolerance=0.01):
        return any(point_segment_distance(p, *self.loop_segments[i]) <= tolerance
                   for i in self.loop_index.near(p - tolerance, p + tolerance))

    def on_outline(self, p, tolerance=0.01):
        return any(point_segment_distance(p, *self.segments[i]) <= tolerance
                   for i in self.index.near(p - tolerance, p + tolerance))


def segment_distances(p, segments):
    """The distances from p to each of the segments (n × 2 × 2)."""
    a, d = segments[:, 0], segments[:, 1] - segments[:, 0]
    n = np.einsum("ij,ij->i", d, d)
    with np.errstate(divide="ignore", invalid="ignore"):
        t = np.where(n > 0, np.clip(np.einsum("ij,ij->i", p - a, d) / n, 0.0, 1.0), 0.0)
    return np.linalg.norm(p - (a + t[:, None] * d), axis=1)


def rotation(angle):
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, -s], [s, c]])


def fit_motion(pairs):
    """The rigid motion (no reflection) taking the first points of the pairs closest to
    the second (Procrustes)."""
    P, Q = np.array([a for a, _ in pairs]), np.array([b for _, b in pairs])
    pc, qc = P.mean(axis=0), Q.mean(axis=0)
    H = (P - pc).T @ (Q - qc)
    R = rotation(math.atan2(H[0, 1] - H[1, 0], H[0, 0] + H[1, 1]))
    return R, qc - pc @ R.T


def corners(points, edges):
    """The piece's corners (vertices where its boundary turns: the printed outline has a
    vertex there, as the writer drops points on straight runs) and, for each, the corner
    the boundary runs straight to next."""
    following = dict(edges)
    preceding = {b: a for a, b in edges}
    corner = []
    for v in range(len(points)):
        if v not in following or v not in preceding:
            continue
        p, q, r = points[preceding[v]], points[v], points[following[v]]
        d1, d2 = q - p, r - q
        turn = abs(d1[0] * d2[1] - d1[1] * d2[0])
        if turn > 1e-7 * float((r - p) @ (r - p)) or d1 @ d2 <= 0:
            corner.append(v)
    is_corner = set(corner)
    runs = []
    for a in corner:
        b, steps = following[a], 0
        while b not in is_corner and steps < len(points):
            b, steps = following.get(b, a), steps + 1
        if b != a:
            runs.append((a, b))
    return corner, runs


def placements(points, edges, outline, folds=(), fold_index=None, accept=None):
    """Every place the piece fits on the printed outline: rigid motions (R, t) putting each
    of its boundary vertices (`points`) and the middle of each of its boundary edges
    (`edges`, index pairs into `points`) on a cut loop or a tab base, and at least one
    of its vertices on a cut loop (a piece with a tab on every edge is not found on its
    tab bases alone where its cut loop is printed elsewhere).

    Each is found from an anchor: a corner a of the piece and the straight run of its
    boundary to the next corner b, laid on a printed vertex along one of the printed
    lines leaving it (a cut segment or a tab base, no longer than the run: shorter where
    a tab begins or a narrowed tab's base ends); kept when the corners nearest a and up
    to 16 more spread over the piece land near printed vertices (one of four or more may
    miss); then refined on the
    corners near a and on every vertex (Procrustes) and verified. The three longest runs,
    each from both ends, are anchors: the piece is found wherever one of them is printed
    as drawn. No candidate is pruned by a vote over the whole sheet, so every place of a
    congruent piece is found; which piece takes which place is decided afterwards, for
    all pieces together (`assign`).

    `accept(R, t)`, if given, must hold too (the printed creases agree with the piece).

    Returns [(R, t, landed, on_folds, turns)] one per place (`landed`: the printed
    vertices under the piece's vertices, a frozenset; `on_folds`: how many of the piece's
    fold edges' middles lie on printed fold lines: of a symmetric piece's turns at one
    place, the one that matches its folds is kept; folds under the pattern's smallest fold
    angle are not drawn, so a preference, not a test; `turns`: every motion (R, t) that
    fits the place as well, more than one for a symmetric piece, which the printed seam
    IDs decide between)."""
    corner, runs = corners(points, edges)
    if not runs:
        return []
    length = {run: float(np.linalg.norm(points[run[1]] - points[run[0]])) for run in runs}
    runs.sort(key=lambda run: -length[run])
    anchors = [(a, b, length[(a, b)]) for a, b in runs[:3]] + [(b, a, length[(a, b)]) for a, b in runs[:3]]
    seen = set()
    places = {}
    for a, b, run in anchors:
        d = points[b] - points[a]
        # Lines of at least 0.2 mm (or the whole run when it is shorter) give the turn
        # within 4e-4 rad: 0.008 mm at the 20 mm around a, the coarser test farther.
        take = (outline.line_length <= run + 0.01) & (outline.line_length >= min(run, 0.2) - 0.01)
        q = outline.points[outline.line_vertex[take]]
        theta = outline.line_angle[take] - math.atan2(d[1], d[0])

        def land(i, k):
            """Where the vertices i land by the candidates k."""
            u = points[i] - points[a]
            cos, sin = np.cos(theta[k])[:, None], np.sin(theta[k])[:, None]
            return q[k][:, None, :] + np.stack([cos * u[:, 0] - sin * u[:, 1], sin * u[:, 0] + cos * u[:, 1]], axis=-1)
        others = [c for c in corner if c != a]
        distance = np.linalg.norm(points[others] - points[a], axis=1)
        by_distance = np.argsort(distance, kind="stable")
        nearest = [others[i] for i in by_distance[:8] if distance[i] <= 20.0]
        # Up to 16 more corners spread over the piece (to 500 mm: the coarser test).
        rest = [i for i in by_distance[len(nearest):] if distance[i] <= 500.0]
        spread = [others[rest[j]] for j in np.unique(np.linspace(0, len(rest) - 1, 16).astype(int))] if rest else []
        allowed = 1 if len(nearest) + len(spread) >= 4 else 0
        kept = np.arange(len(q))
        misses = np.zeros(len(q), dtype=int)
        for check, size in ((nearest, 0.05), (spread, 0.2)):
            if check:
                misses = misses + np.sum(~outline.near_vertices(land(np.array(check), kept), size), axis=1)
                kept, misses = kept[misses <= allowed], misses[misses <= allowed]
        for k in kept:
            angle = float(theta[k]) % (2 * math.pi)
            R = rotation(angle)
            t = q[k] - points[a] @ R.T
            key = (round(angle / 1e-3) % round(2 * math.pi / 1e-3), *np.round(t / 0.05).astype(int))
            if key in seen:
                continue
            seen.add(key)
            found = verify(points, edges, outline, R, t, [a] + nearest)
            if found is None:
                continue
            R, t, landed = found
            if accept is not None and not accept(R, t):
                continue
            on_folds = 0
            if fold_index is not None:
                for m in np.array(list(folds)).reshape(-1, 2) @ R.T + t:
                    near = fold_index.near(m - 0.01, m + 0.01)
                    on_folds += any(point_segment_distance(m, *fold_index.segments[i]) <= 0.01 for i in near)
            if landed not in places or on_folds > places[landed][3]:
                places[landed] = (R, t, landed, on_folds, [(R, t)])
            elif on_folds == places[landed][3]:
                # Another way the piece fits the same place (a symmetric piece).
                places[landed][4].append((R, t))
    return list(places.values())


def verify(points, edges, outline, R, t, around):
    """(R, t refined, landed vertices) when the motion puts the piece on the outline;
    refined first on the vertices `around` the anchor, then on all."""
    for check in (around, range(len(points))):
        moved = points[list(check)] @ R.T + t
        matched = []
        for p0, p in zip(points[list(check)], moved):
            k = outline.vertex_at(p, 0.05)
            if k is not None:
                matched.append((p0, outline.points[k]))
            elif not outline.on_outline(p, 0.05):
                return None
        if len(matched) >= 2:
            R, t = fit_motion(matched)
    moved = points @ R.T + t
    landed = set()
    for p in moved:
        k = outline.vertex_at(p, 0.01)
        if k is not None:
            landed.add(k)
        elif not outline.on_outline(p):
            return None
    for a, b in edges:
        if not outline.on_outline((moved[a] + moved[b]) / 2):
            return None
    if not any(outline.on_loop(p) for p in moved):
        return None
    return R, t, frozenset(landed)


def assign(domains):
    """Pieces to places: `domains[i]` lists the places piece i fits (frozensets of printed
    vertices), best first. Congruent pieces fit each other's places, so each is not
    placed on its own, greedily: the pieces are assigned together so that no printed
    vertex is claimed by two pieces (an assignment problem, solved by backtracking over
    the candidate places, most constrained piece first, bounded by a maximum matching of
    the rest onto the places still free). Where geometry allows several complete
    assignments (congruent pieces swapped), each piece's places are tried in its order:
    the order is the tie-break. Returns {piece: index into its domain} placing as many pieces
    as can be placed."""
    parent = list(range(len(domains)))
    owner = {}
    for i, places in enumerate(domains):
        for place in places:
            for k in place:
                if k in owner:
                    parent[find(parent, i)] = find(parent, owner[k])
                else:
                    owner[k] = i
    components = defaultdict(list)
    for i in range(len(domains)):
        components[find(parent, i)].append(i)
    result = {}
    for component in components.values():
        result.update(assign_component(domains, component))
    return result


def assign_component(domains, component):
    used = set()
    chosen, best = {}, {}
    budget = [100000]

    def free(i):
        return [k for k, place in enumerate(domains[i]) if used.isdisjoint(place)]

    def bound(rest):
        """The most of `rest` that can still be placed, counting places that overlap
        without being equal as apart (an upper bound)."""
        options = {i: [domains[i][k] for k in free(i)] for i in rest}
        match = {}

        def augment(i, seen):
            for place in options[i]:
                if place not in seen:
                    seen.add(place)
                    if place not in match or augment(match[place], seen):
                        match[place] = i
                        return True
            return False
        return sum(augment(i, set()) for i in rest)

    def search(rest):
        nonlocal best
        if budget[0] <= 0 or len(chosen) + bound(rest) <= len(best):
            return
        budget[0] -= 1
        if not rest:
            best = dict(chosen)
            return
        options = {i: free(i) for i in rest}
        i = min(rest, key=lambda j: (len(options[j]), j))
        others = [j for j in rest if j != i]
        for k in options[i]:
            chosen[i] = k
            used.update(domains[i][k])
            search(others)
            used.difference_update(domains[i][k])
            del chosen[i]
            if len(best) == len(component):
                return
        search(others)
    search(list(component))
    return best


def audit(out, clearance):
    scale = 1.0
    report_path = os.path.join(out, "report.json")
    if os.path.exists(report_path):
        scale = json.load(open(report_path)).get("pattern", {}).get("scale", 1.0)
    v, vt, faces, unit, face_groups = read_obj(os.path.join(out, "model.obj"))
    flat = vt * UNIT_MM[unit] * scale
    view, loops, loop_pieces, lines, texts = parse_svg(os.path.join(out, "pattern.svg"))
    tab_bases = lines.get("fold-tab", [])
    # Boundary half-edges of the flat pattern (vt indices) and their 3D ends.
    half = {}
    vt_to_v = {}
    for f in faces:
        for k in range(3):
            (va, ta), (vb, tb) = f[k], f[(k + 1) % 3]
            half[(ta, tb)] = (va, vb)
            vt_to_v[ta] = va
    boundary = [(a, b) for (a, b) in half if (b, a) not in half]
    # Copies of one 3D vertex (a seam's two sides, computed apart, may differ in the last
    # digits): positions on a grid a millionth of the model's size.
    V = np.array(v)
    step = 1e-6 * max(float(np.linalg.norm(V.max(axis=0) - V.min(axis=0))), 1e-300)
    key3 = {i: tuple(np.round(V[i] / step).astype(np.int64)) for i in range(len(v))}
    by_ends = defaultdict(list)
    for a, b in boundary:
        pa, pb = key3[vt_to_v[a]], key3[vt_to_v[b]]
        by_ends[frozenset([pa, pb])].append((a, b))
    pairs = [tuple(g) for g in by_ends.values() if len(g) == 2]
    partner = {}
    for x, y in pairs:
        partner[x], partner[y] = y, x
    # Pieces: faces joined by shared vt indices.
    parent = list(range(len(vt)))
    for f in faces:
        for k in (1, 2):
            ra, rb = find(parent, f[0][1]), find(parent, f[k][1])
            parent[ra] = rb
    piece_of = {}
    for f in faces:
        piece_of.setdefault(find(parent, f[0][1]), len(piece_of))
    vt_piece = {t: piece_of[find(parent, t)] for t in range(len(vt)) if find(parent, t) in piece_of}
    members = defaultdict(list)
    for t, piece in vt_piece.items():
        members[piece].append(t)
    # Slits of zero width: a glued pair whose two copies lie on one line of one piece
    # (end to end, as the flat pattern places them): no cut at all, printed as one.
    zero_width = sum(1 for (a, b), (c, d) in pairs
                     if vt_piece.get(a) == vt_piece.get(c)
                     and max(np.linalg.norm(np.subtract(vt[a], vt[d])), np.linalg.norm(np.subtract(vt[b], vt[c])))
                     <= 1e-6 * max(np.linalg.norm(np.subtract(vt[a], vt[b])), 1e-300))
    # Register each piece on the printed outline.
    outline = Outline(loops, loop_pieces, tab_bases)
    outline_points = np.array([p for l in loops for p in l] + [p for ab in tab_bases for p in ab])
    placed = {}
    # Without packing, every piece sits where the mesh's layout put it: one translation
    # (found by a vote over all boundary points) places them all; it is tried first.
    boundary_points = flat[sorted({t for e in boundary for t in e})]
    sample = boundary_points[:: max(1, len(boundary_points) // 300)]
    raw = (outline_points[None, :, :] - sample[:, None, :]).reshape(-1, 2)
    # Votes in bins of 0.01 mm (the SVG's rounding stays inside one), the winner refined
    # to the median of its votes.
    bins = np.round(raw / 0.01).astype(np.int64)
    code = (bins[:, 0] + (1 << 30)) * (1 << 31) + (bins[:, 1] + (1 << 30))
    codes, inverse, counts = np.unique(code, return_inverse=True, return_counts=True)
    shared_t = np.median(raw[inverse.ravel() == np.argmax(counts)], axis=0)

    # The middles of each piece's fold edges (interior edges folded by more than 2°),
    # and the printed fold lines.
    fold_lines = [ab for lid in ("fold-mountain", "fold-valley", "fold-guide") for ab in lines.get(lid, [])]
    fold_index = SegmentIndex(fold_lines, 10.0) if fold_lines else None
    piece_folds = defaultdict(list)
    normal = {}
    for f in faces:
        a, b, c = (np.array(v[x[0]]) for x in f)
        n = np.cross(b - a, c - a)
        normal[tuple(x[1] for x in f)] = n / max(np.linalg.norm(n), 1e-300)
    face_normal = {}
    for f in faces:
        key = tuple(x[1] for x in f)
        for k in range(3):
            face_normal[(f[k][1], f[(k + 1) % 3][1])] = normal[key]
    for (ta, tb), n1 in face_normal.items():
        n2 = face_normal.get((tb, ta))
        if n2 is not None and ta < tb and math.degrees(math.acos(max(-1.0, min(1.0, n1 @ n2)))) > 2.0:
            piece_folds[vt_piece[ta]].append((flat[ta] + flat[tb]) / 2)
    piece_points = []
    for piece in range(len(piece_of)):
        edges = [(a, b) for a, b in boundary if vt_piece[a] == piece]
        idx = sorted({t for e in edges for t in e})
        piece_points.append((edges, idx))
    # The shared translation holds only when it puts every piece on the outline as
    # `placements` does: each vertex and edge's middle on a cut loop or a tab base, a
    # vertex of each piece on a cut loop.
    shared = all(outline.on_outline(flat[i] + shared_t) for _, idx in piece_points for i in idx) and \
        all(outline.on_outline((flat[a] + flat[b]) / 2 + shared_t) for edges, _ in piece_points for a, b in edges) and \
        all(any(outline.on_loop(flat[i] + shared_t) for i in idx) for _, idx in piece_points)

    def settle(piece, points, R, t):
        # Refined on the printed vertices the piece's vertices landed on (Procrustes: the
        # candidates' turns come from a few printed points, rounded by the drawing).
        matched = []
        for p0, p in zip(points, points @ R.T + t):
            k = outline.vertex_at(p, 0.01)
            if k is not None:
                matched.append((p0, outline.points[k]))
        if len(matched) >= 2:
            R, t = fit_motion(matched)
        for i in members[piece]:
            placed[i] = flat[i] @ R.T + t
    # The mesh pieces each piece holds (the OBJ's groups, numbered in the file's order as
    # the SVG's `data-mesh-pieces` numbers them) and its names.
    piece_groups = defaultdict(set)
    for f, face in enumerate(faces):
        piece_groups[vt_piece[face[0][1]]].add(face_groups[f])
    # The printed creases (mountain and valley lines), each along interior edges of its
    # piece; and each piece's interior edges.
    creases = [ab for lid in ("fold-mountain", "fold-valley") for ab in lines.get(lid, [])]
    crease_index = SegmentIndex(creases, 10.0) if creases else None
    piece_inner = defaultdict(list)
    for (ta, tb) in half:
        if ta < tb and (tb, ta) in half:
            piece_inner[vt_piece[ta]].append((flat[ta], flat[tb]))
    domains, motions = [], []
    for piece, (edges, idx) in enumerate(piece_points):
        points = flat[idx]
        if shared:
            settle(piece, points, np.eye(2), shared_t)
            continue
        local = {t: k for k, t in enumerate(idx)}
        triangles = np.array([flat[[c[1] for c in face]] for face in faces if vt_piece[face[0][1]] == piece])
        inner = np.array(piece_inner[piece]).reshape(-1, 2, 2)
        rim = np.array([(flat[a], flat[b]) for a, b in edges])

        def creases_agree(R, t):
            """No printed crease runs through the placed piece off its interior edges (an
            outline printed away from its piece's creases is not that piece's place)."""
            if crease_index is None:
                return True
            moved = triangles @ R.T + t
            lo, hi = moved.min(axis=(0, 1)), moved.max(axis=(0, 1))
            for i in crease_index.near(lo, hi):
                m = (creases[i][0] + creases[i][1]) / 2
                if np.any(m < lo) or np.any(m > hi) or not any(inside_triangle(m, *tri) for tri in moved):
                    continue
                if segment_distances(m, rim @ R.T + t).min() <= 0.01:
                    continue
                if not len(inner) or segment_distances(m, inner @ R.T + t).min() > 0.01:
                    return False
            return True
        found = placements(points, [(local[a], local[b]) for a, b in edges], outline, piece_folds[piece], fold_index,
                           creases_agree)
        # A piece whose own name is printed: the places with the name inside it (where
        # there are any).
        names = {name for name, _ in piece_groups[piece]}
        name_points = [t["centre"] for t in texts if t["class"] == "piece" and t["text"] in names]

        def named_here(motion):
            R, t = motion[0], motion[1]
            moved = triangles @ R.T + t
            lo, hi = moved.min(axis=(0, 1)), moved.max(axis=(0, 1))
            return any(np.all(q >= lo) and np.all(q <= hi) and any(inside_triangle(q, *tri) for tri in moved)
                       for q in name_points)
        found = [m for m in found if named_here(m)] or found
        # Best first. Geometry decides which places a piece fits, and the assignment below
        # which of them it takes; only where congruent pieces could swap places does this
        # order decide: first the places with more of the piece's folds on printed fold
        # lines (geometry still), then, as the tie-break, the places whose cut loop the
        # SVG says holds this piece (`data-mesh-pieces`, the file's own word).
        held = {number for _, number in piece_groups[piece]}

        def says_here(motion):
            loops_held = {outline.mesh_pieces[k] for k in motion[2]} - {None}
            return loops_held == {frozenset(held)}
        found.sort(key=lambda m: (-m[3], not says_here(m)))
        domains.append([m[2] for m in found])
        motions.append(found)
    unregistered = 0
    if not shared:
        # Congruent pieces fit each other's places: all pieces are placed together, no
        # printed vertex under two of them (registering them one by one, the first could
        # take a place only a later one fits).
        chosen = assign(domains)
        for piece, (edges, idx) in enumerate(piece_points):
            if piece in chosen:
                R, t = motions[piece][chosen[piece]][:2]
                settle(piece, flat[idx], R, t)
            else:
                unregistered += 1
        # A piece with a symmetry (a strip turned end for end) fits its place in more than
        # one way, which geometry cannot tell apart; its printed seam IDs can: the motion
        # kept is the one under which most IDs printed on it find the same ID printed by
        # the other copy of the edge they stand beside.
        seam_texts = [t for t in texts if t["class"] == "seam"]
        for piece, k in chosen.items():
            same = motions[piece][k][4]
            if len(same) < 2:
                continue
            edges, idx = piece_points[piece]
            moved = np.array([placed[c[1]] for face in faces if vt_piece[face[0][1]] == piece for c in face])
            moved = moved.reshape(-1, 3, 2)
            lo, hi = moved.min(axis=(0, 1)), moved.max(axis=(0, 1))
            mine = [t for t in texts_in(seam_texts, lo, hi) if any(inside_triangle(t["centre"], *tri) for tri in moved)]
            if not mine:
                continue

            def agreeing():
                count = 0
                for label in mine:
                    c = label["centre"]
                    a, b = min(edges, key=lambda e: point_segment_distance(c, placed[e[0]], placed[e[1]]))
                    pa, pb = partner.get((a, b), (None, None))
                    if pa is None:
                        continue
                    radius = 4 * label["size"] + 2
                    count += any(o["text"] == label["text"] and o is not label
                                 and point_segment_distance(o["centre"], placed[pa], placed[pb]) <= radius
                                 for o in seam_texts)
                return count
            scores = []
            for j, (R, t) in enumerate(same):
                settle(piece, flat[idx], R, t)
                scores.append((agreeing(), -j))
            settle(piece, flat[idx], *same[-max(scores)[1]])
    result = {"pieces": len(piece_of), "pieces_unregistered": unregistered, "glued_edge_pairs": len(pairs),
              "zero_width_slits": zero_width}
    if unregistered:
        return result
    base_index = SegmentIndex(tab_bases, 10.0)

    def has_tab(e):
        a, b = placed[e[0]], placed[e[1]]
        length = np.linalg.norm(b - a)
        for i in base_index.near(np.minimum(a, b) - 0.01, np.maximum(a, b) + 0.01):
            p, q = tab_bases[i]
            if point_segment_distance(p, a, b) <= 1e-3 and point_segment_distance(q, a, b) <= 1e-3:
                # Overlapping the copy by more than a rounding.
                along = sorted([(p - a) @ (b - a) / length, (q - a) @ (b - a) / length])
                if min(along[1], length) - max(along[0], 0.0) > 1e-3:
                    return True
        return False
    tab_counts = Counter()
    for x, y in pairs:
        tab_counts[has_tab(x) + has_tab(y)] += 1
    result.update({"pairs_tab_one": tab_counts[1], "pairs_tab_both": tab_counts[2], "pairs_tab_none": tab_counts[0]})
    # Seams: glued pairs consecutive on both copies, not across a slit's apex.
    next_edge = {a: (a, b) for a, b in boundary}
    seam_parent = {e: e for e in partner}
    for e in partner:
        n = next_edge.get(e[1])
        if n is None or n not in partner or partner[e] == n:
            continue
        # The next edge's partner must end where this edge's partner starts.
        if partner[n][1] == partner[e][0]:
            ra, rb = find(seam_parent, e), find(seam_parent, n)
            seam_parent[ra] = rb
    sides = defaultdict(list)
    for e in partner:
        sides[find(seam_parent, e)].append(e)
    seams = {}
    for root, edges in sides.items():
        other = find(seam_parent, partner[edges[0]])
        seams.setdefault(frozenset([root, other]), (root, other))
    seam_labels = [t for t in texts if t["class"] == "seam"]
    side_segments = [(root, placed[a], placed[b], vt_piece[a]) for root, edges in sides.items() for a, b in edges]
    side_index = SegmentIndex([(a, b) for _, a, b, _ in side_segments], 10.0)
    # The piece a point is printed on.
    piece_triangles = [(vt_piece[f[0][1]], np.array([placed[c[1]] for c in f])) for f in faces]
    triangle_index = SegmentIndex([(t.min(axis=0), t.max(axis=0)) for _, t in piece_triangles], 10.0)

    def piece_at(p):
        for i in triangle_index.near(p, p):
            piece, t = piece_triangles[i]
            if inside_triangle(p, *t):
                return piece
        return None
    assigned = defaultdict(list)
    for label in seam_labels:
        c = label["centre"]
        here = piece_at(c)
        best, best_d, radius = None, math.inf, 4 * label["size"] + 2
        while best is None and radius < 1e4:
            for i in side_index.near(c - radius, c + radius):
                root, a, b, piece = side_segments[i]
                if piece != here:
                    continue
                d = point_segment_distance(c, a, b)
                if d < best_d:
                    best, best_d = root, d
            radius *= 4
        if best is not None:
            assigned[best].append(label["text"])
    counts = Counter()
    for root, other in seams.values():
        ta, tb = assigned.get(root, []), assigned.get(other, [])
        if ta and tb:
            counts["both" if set(ta) & set(tb) else "mismatch"] += 1
        elif ta or tb:
            counts["one"] += 1
        else:
            counts["none"] += 1
    reused = sum(1 for _, n in Counter(l["text"] for l in seam_labels).items() if n > 2)
    result.update({"seams": len(seams), "seams_id_both": counts["both"], "seams_id_one_side": counts["one"],
                   "seams_id_mismatch": counts["mismatch"], "seams_id_none": counts["none"],
                   "seam_ids_reused": reused, "seam_labels": len(seam_labels)})
    # Tabs: the cut path's points off the piece outlines are the tabs' outer points.
    piece_segments = [(placed[a], placed[b]) for a, b in boundary]
    piece_index = SegmentIndex(piece_segments, 10.0)

    def on_outline(p):
        return any(point_segment_distance(p, *piece_segments[i]) <= 1e-3
                   for i in piece_index.near(p - 0.01, p + 0.01))
    depth_min = math.inf
    cut_segments = []
    vertex_points = np.array([placed[i] for i in sorted({t for e in boundary for t in e})])
    vertex_index = SegmentIndex([(p, p) for p in vertex_points], 10.0)
    for li, l in enumerate(loops):
        # The outline's vertices a cut segment passes through (a corner between two tabs
        # whose slanted sides run on in one line) become points of the path.
        refined = []
        for i in range(len(l)):
            a, b = l[i], l[(i + 1) % len(l)]
            refined.append(a)
            d = b - a
            length2 = d @ d
            inner = []
            for k in vertex_index.near(np.minimum(a, b) - 1e-3, np.maximum(a, b) + 1e-3):
                q = vertex_points[k]
                t = (q - a) @ d / length2 if length2 > 0 else 0.0
                far = min(np.linalg.norm(q - a), np.linalg.norm(q - b)) > 2e-3
                if far and 0 < t < 1 and point_segment_distance(q, a, b) <= 1e-3:
                    inner.append((t, tuple(q)))
            refined.extend(np.array(q) for _, q in sorted(set(inner)))
        l = np.array(refined)
        loops[li] = l
        n = len(l)
        outer = [not on_outline(p) for p in l]
        # Each tab: a run of outer points and the segments touching it (one number).
        tab_of_point = [None] * n
        start = next((i for i in range(n) if not outer[i]), None)
        count = 0
        if start is not None:
            for k in range(1, n + 1):
                i = (start + k) % n
                if outer[i]:
                    if not outer[(i - 1) % n]:
                        count += 1
                    tab_of_point[i] = (li, count)
        for i in range(n):
            j = (i + 1) % n
            tab = tab_of_point[i] or tab_of_point[j]
            # A tab's slanted side is measured but for its first twice the clearance at
            # its base corner, where the outline it stands on meets it.
            a, b = l[i], l[j]
            if tab is not None and (tab_of_point[i] is None) != (tab_of_point[j] is None):
                base, far = (a, b) if tab_of_point[i] is None else (b, a)
                length = np.linalg.norm(far - base)
                base = base + (far - base) * min(0.9, 2 * clearance / max(length, 1e-12))
                a, b = (base, far) if tab_of_point[i] is None else (far, base)
            cut_segments.append((li, i, a, b, tab))
        # Each tab's depth: its outer points' largest distance from the line through the
        # outline points on either side of it.
        depth = {}
        if start is not None:
            run = []
            for k in range(1, n + 1):
                i = (start + k) % n
                if outer[i]:
                    run.append(i)
                elif run:
                    a, b = l[(run[0] - 1) % n], l[i]
                    u = (b - a) / max(np.linalg.norm(b - a), 1e-12)
                    depth[tab_of_point[run[0]]] = max(abs((l[j] - a)[0] * u[1] - (l[j] - a)[1] * u[0]) for j in run)
                    run = []
        if depth:
            depth_min = min(depth_min, min(depth.values()))
    index = SegmentIndex([(a, b) for _, _, a, b, _ in cut_segments], 10.0)
    # Arc length along each loop up to each of its points.
    cumulative = []
    for l in loops:
        steps = np.linalg.norm(np.roll(l, -1, axis=0) - l, axis=1)
        cumulative.append(np.concatenate([[0.0], np.cumsum(steps)]))

    def along(loop, i, j):
        """The shorter way along the loop between the end of segment i and the start of
        segment j (or the other way round)."""
        c = cumulative[loop]
        total = c[-1]
        i, j = min(i, j), max(i, j)
        inner = c[j] - c[i + 1]
        return min(inner, total - (c[j + 1] - c[i]))
    crossings, slit_close, tab_close = 0, 0, 0
    tab_gap, piece_gap, slit_gap = math.inf, math.inf, math.inf
    loop_piece = []
    for l in loops:
        loop_piece.append(None)
    same = lambda p, q: np.linalg.norm(p - q) <= 1e-6
    for x, (lx, ix, a, b, tx) in enumerate(cut_segments):
        lo, hi = np.minimum(a, b) - max(clearance, 1.0), np.maximum(a, b) + max(clearance, 1.0)
        for y in index.near(lo, hi):
            if y <= x:
                continue
            ly, iy, c, d, ty = cut_segments[y]
            if lx == ly and (iy == (ix + 1) % len(loops[lx]) or ix == (iy + 1) % len(loops[lx])):
                continue
            if segments_cross(a, b, c, d):
                crossings += 1
                continue
            shared = [p for p in (a, b) if same(p, c) or same(p, d)]
            if tx is not None and tx == ty:
                continue
            if tx or ty:
                dist = segment_distance(a, b, c, d)
                tab_gap = min(tab_gap, dist)
                if dist < clearance - 1e-9 and os.environ.get("AUDIT_DEBUG"):
                    print("close", dist, a, b, c, d, tx, ty, file=sys.stderr)
                tab_close += dist < clearance - 1e-9
            elif lx != ly:
                piece_gap = min(piece_gap, segment_distance(a, b, c, d))
            elif not shared and along(lx, ix, iy) > 3 * clearance:
                # (Two lines of one outline near each other only because the outline
                # runs on between them in a few short steps are no slit.)
                dist = segment_distance(a, b, c, d)
                slit_gap = min(slit_gap, dist)
                slit_close += dist < clearance - 1e-9
    fin = lambda x: None if math.isinf(x) else round(x, 6)
    result.update({"tab_depth_min_mm": fin(depth_min), "tab_clearance_min_mm": fin(tab_gap),
                   "tabs_closer_than_clearance": tab_close, "cut_crossings": crossings,
                   "piece_gap_min_mm": fin(piece_gap), "slit_gap_min_mm": fin(slit_gap),
                   "slit_pairs_closer_than_clearance": slit_close})
    result.update(label_problems(loops, lines, texts))
    dxf_path = os.path.join(out, "pattern.dxf")
    if os.path.exists(dxf_path):
        result["dxf"] = dxf_layers(dxf_path, view, lines)
    return result


def label_problems(loops, lines, texts):
    """Labels whose glyph box (0.55 em a character, 0.7 em high) meets a line or another
    label, or leaves the cut loops."""
    segments = [(l[i], l[(i + 1) % len(l)]) for l in loops for i in range(len(l))]
    segments += [ab for group in lines.values() for ab in group]
    index = SegmentIndex(segments, 10.0)

    def box(t):
        u = np.array([math.cos(t["angle"]), math.sin(t["angle"])])
        w = np.array([-u[1], u[0]])
        hw, hh = 0.5 * 0.55 * t["size"] * len(t["text"]), 0.35 * t["size"]
        c = t["centre"]
        return [c - hw * u - hh * w, c + hw * u - hh * w, c + hw * u + hh * w, c - hw * u + hh * w]

    def inside(p):
        crossings = 0
        for l in loops:
            a, b = l, np.roll(l, -1, axis=0)
            cond = (a[:, 1] > p[1]) != (b[:, 1] > p[1])
            with np.errstate(divide="ignore", invalid="ignore"):
                x = a[:, 0] + (p[1] - a[:, 1]) / (b[:, 1] - a[:, 1]) * (b[:, 0] - a[:, 0])
            crossings += int(np.sum(cond & (p[0] < x)))
        return crossings % 2 == 1
    over, outside = 0, 0
    boxes = [box(t) for t in texts]
    for k, corners in enumerate(boxes):
        lo, hi = np.min(corners, axis=0), np.max(corners, axis=0)
        edges = [(corners[i], corners[(i + 1) % 4]) for i in range(4)]
        hit = False
        for i in index.near(lo, hi):
            a, b = segments[i]
            if any(segments_cross(a, b, p, q) for p, q in edges) or inside_box(corners, a) or inside_box(corners, b):
                hit = True
                break
        for other in boxes[:k]:
            if any(inside_box(other, p) for p in corners) or any(inside_box(corners, p) for p in other):
                hit = True
        over += hit
        outside += not all(inside(p) for p in corners)
    return {"labels_over_lines": over, "labels_outside": outside, "labels": len(texts)}


def texts_in(texts, lo, hi):
    """The texts whose centre lies in the box [lo, hi]."""
    return [t for t in texts if np.all(t["centre"] >= lo) and np.all(t["centre"] <= hi)]


def inside_triangle(p, a, b, c):
    def cross(u, w):
        return u[0] * w[1] - u[1] * w[0]
    s = [cross(b - a, p - a), cross(c - b, p - b), cross(a - c, p - c)]
    return all(x >= 0 for x in s) or all(x <= 0 for x in s)


def inside_box(corners, p):
    def cross(u, w):
        return u[0] * w[1] - u[1] * w[0]
    signs = [cross(corners[(i + 1) % 4] - corners[i], p - corners[i]) for i in range(4)]
    return all(s > 0 for s in signs) or all(s < 0 for s in signs)


def dxf_layers(path, view, lines):
    import ezdxf
    doc = ezdxf.readfile(path)
    msp = doc.modelspace()
    lo = np.array(doc.header.get("$EXTMIN", (0, 0, 0))[:2])
    hi = np.array(doc.header.get("$EXTMAX", (0, 0, 0))[:2])
    margin = (view[2] - (hi[0] - lo[0])) / 2
    units = {4: 1.0, 5: 10.0, 1: 25.4}.get(doc.header.get("$INSUNITS", 4), 1.0)
    # DXF point (in its unit) → the SVG's y-up millimetres.
    to_svg = lambda p: np.array([(p[0] - lo[0]) * units + margin, -((hi[1] - p[1]) * units + margin)])
    svg_lines = [(a, b, lid) for lid, group in lines.items() for a, b in group]
    svg_index = SegmentIndex([(a, b) for a, b, _ in svg_lines], 10.0)

    def svg_layer(a, b):
        for i in svg_index.near(np.minimum(a, b) - 1e-3, np.maximum(a, b) + 1e-3):
            p, q, lid = svg_lines[i]
            if max(np.linalg.norm(p - a), np.linalg.norm(q - b)) <= 1e-3 or \
                    max(np.linalg.norm(p - b), np.linalg.norm(q - a)) <= 1e-3:
                return lid
        return "unmatched"
    kinds = defaultdict(set)
    counts = Counter()
    for e in msp:
        layer = e.dxf.layer
        counts[layer] += 1
        if e.dxftype() == "LINE":
            a, b = to_svg(e.dxf.start), to_svg(e.dxf.end)
            kinds[layer].add(svg_layer(a, b))
        else:
            kinds[layer].add(e.dxftype())
    return {"entities": dict(counts), "kinds": {k: sorted(v) for k, v in kinds.items()},
            "layers_apart": all(len(v) == 1 for v in kinds.values())}


def main():
    args = sys.argv[1:]
    clearance = 1.0
    if "--clearance" in args:
        i = args.index("--clearance")
        clearance = float(args[i + 1])
        del args[i:i + 2]
    if len(args) != 1:
        sys.exit(__doc__)
    print(json.dumps(audit(args[0], clearance), sort_keys=True))


if __name__ == "__main__":
    main()
