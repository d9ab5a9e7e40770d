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
- `cut_crossings`: cut segments that cross; `piece_gap_min_mm`: the least distance
  between the cut loops of different pieces; `slit_gap_min_mm` and
  `slit_pairs_closer_than_clearance`: within one loop, segments that share no point and
  come closer than the clearance (narrow slits of a net);
- `labels_over_lines`, `labels_outside`: labels whose text box meets a line or leaves
  the cut loops;
- `dxf`: the layers of the DXF's entities and whether each layer holds one kind of line
  of the SVG (`layers_apart`): cut, mountain, valley, tab score, guide, ... never mixed.

Pieces are registered onto the SVG one by one (each may have been turned and moved by
sheet packing): rotations from matching edge lengths, translations by voting, verified
by every boundary point of the piece lying on the printed outline.
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
    v, vt, faces, unit, group, groups = [], [], [], "mm", "", []
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
            group = " ".join(p[1:])
    return v, np.array(vt), faces, unit, groups


UNIT_MM = {"mm": 1.0, "cm": 10.0, "m": 1000.0, "in": 25.4}


def parse_svg(path):
    root = ET.parse(path).getroot()
    layers = {}
    for g in root.iter(SVG + "g"):
        if g.get("id"):
            layers[g.get("id")] = g
    view = [float(x) for x in root.get("viewBox").split()]
    loops = []
    for p in layers["cut"].iter(SVG + "path"):
        for ring in p.get("d").split("Z"):
            pts = [(float(x), -float(y)) for x, y in re.findall(r"[ML]\s*([-\d.e+]+),([-\d.e+]+)", ring)]
            if pts:
                loops.append(np.array(pts))
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
    return view, loops, lines, texts


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


def register(piece_points, piece_edges, outline, claimed, folds=(), fold_index=None, near=None, tolerance=2e-3):
    """The rigid motions (R, t, outline points landed on) putting every point of the
    piece on the printed outline, on points no piece registered before has claimed, and
    the middle of every fold edge of the piece (`folds`) on a printed fold line (a piece
    whose outline is symmetric goes the one way its folds are drawn). With `near`
    (centre, radius), only the outline within the radius of the centre votes (a piece
    whose name is printed: it lies around its name)."""
    outline_segments, outline_points, keys, point_index = outline
    voting_segments = outline_segments
    if near is not None:
        centre, radius = near
        close = [ab for ab in outline_segments if np.linalg.norm((ab[0] + ab[1]) / 2 - centre) <= radius]
        if close:
            voting_segments = close
            outline_points = np.array([p for ab in close for p in ab])
    seg = np.array([[a, b] for a, b in voting_segments])
    seg_len = np.linalg.norm(seg[:, 1] - seg[:, 0], axis=1)
    seg_angle = np.arctan2(seg[:, 1, 1] - seg[:, 0, 1], seg[:, 1, 0] - seg[:, 0, 0])
    order = np.argsort(seg_len)
    sorted_len = seg_len[order]
    votes = Counter()
    # An exact angle of each bin (a bin is 1e-4 rad wide: 0.025 mm at 250 mm).
    exact = {0: 0.0}
    for a, b in piece_edges[:400]:
        d = b - a
        length = float(np.hypot(*d))
        lo, hi = np.searchsorted(sorted_len, [length - tolerance, length + tolerance])
        for k in order[lo:hi]:
            theta = (seg_angle[k] - math.atan2(d[1], d[0])) % (2 * math.pi)
            key = round(theta / 1e-4) % round(2 * math.pi / 1e-4)
            votes[key] += 1
            exact[key] = theta
    # (Without a name to look near, congruent pieces turned every way vote for many
    # rotations: more are tried.)
    candidates = [0] + [k for k, _ in votes.most_common(8 if near is not None else 16)]
    found = []
    for k in candidates:
        theta = exact.get(k, k * 1e-4)
        c, s = math.cos(theta), math.sin(theta)
        R = np.array([[c, -s], [s, c]])
        turned = piece_points @ R.T
        sample = turned[:: max(1, len(turned) // 60)]
        differences = np.round((outline_points[None, :, :] - sample[:, None, :]) / tolerance).astype(np.int64)
        # One integer per translation (2^30 steps of the tolerance either way).
        code = (differences[..., 0] + (1 << 30)) * (1 << 31) + (differences[..., 1] + (1 << 30))
        codes, counts = np.unique(code.ravel(), return_counts=True)
        # Every translation voted for by most of the sample (a congruent piece elsewhere
        # gets as many votes as the right place).
        order = np.argsort(-counts)
        best = codes[order][counts[order] >= 0.25 * counts.max()][:400]
        translations = [np.array([(int(c) >> 31) - (1 << 30), (int(c) & ((1 << 31) - 1)) - (1 << 30)]) * tolerance
                        for c in best]
        if counts.max() < 3:
            # Too few of the piece's points are vertices of the printed outline (a small
            # piece whose sides run on in tabs): every outline point under each of its
            # points.
            translations = [q - p for p in turned[:12] for q in outline_points]
        for t in translations:
            moved = turned + t
            ok = True
            landed = []
            for p in moved:
                key = tuple(np.round(p / tolerance).astype(int))
                if key in keys:
                    if key in claimed:
                        ok = False
                        break
                    landed.append(key)
                    continue
                near = point_index.near(p - 0.01, p + 0.01)
                if not any(point_segment_distance(p, *outline_segments[i]) <= 0.01 for i in near):
                    ok = False
                    break
            if ok:
                # The middle of every boundary edge on the outline too (a piece moved by
                # one face along a row of congruent faces has its points on other
                # pieces' outlines, its edges across them).
                for a, b in piece_edges:
                    m = ((a + b) / 2) @ R.T + t
                    near = point_index.near(m - 0.01, m + 0.01)
                    if not any(point_segment_distance(m, *outline_segments[i]) <= 0.01 for i in near):
                        ok = False
                        break
            if ok:
                # How many of the piece's folds lie on printed fold lines: the turn of a
                # symmetric outline that matches its folds is preferred (folds under the
                # pattern's smallest fold angle are not drawn: a preference, not a test).
                on_folds = 0
                if fold_index is not None:
                    for m in np.array(list(folds)).reshape(-1, 2) @ R.T + t:
                        near = fold_index.near(m - 0.01, m + 0.01)
                        on_folds += any(point_segment_distance(m, *fold_index.segments[i]) <= 0.01 for i in near)
                found.append((R, t, landed, on_folds))
    found.sort(key=lambda m: -m[3])
    return [m[:3] for m in found]


def audit(out, clearance):
    scale = 1.0
    report_path = os.path.join(out, "report.json")
    if os.path.exists(report_path):
        scale = json.load(open(report_path)).get("pattern", {}).get("scale", 1.0)
    v, vt, faces, unit, face_groups = read_obj(os.path.join(out, "model.obj"))
    flat = vt * UNIT_MM[unit] * scale
    view, loops, lines, texts = parse_svg(os.path.join(out, "pattern.svg"))
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

    def find(x):
        while parent[x] != x:
            parent[x] = parent[parent[x]]
            x = parent[x]
        return x
    for f in faces:
        for k in (1, 2):
            ra, rb = find(f[0][1]), find(f[k][1])
            parent[ra] = rb
    piece_of = {}
    for f in faces:
        piece_of.setdefault(find(f[0][1]), len(piece_of))
    vt_piece = {t: piece_of[find(t)] for t in range(len(vt)) if find(t) in piece_of}
    members = defaultdict(list)
    for t, piece in vt_piece.items():
        members[piece].append(t)
    # Register each piece on the printed outline.
    outline = [(l[i], l[(i + 1) % len(l)]) for l in loops for i in range(len(l))] + list(tab_bases)
    outline_points = np.array([p for l in loops for p in l] + [p for ab in tab_bases for p in ab])
    outline_keys = {tuple(np.round(p / 2e-3).astype(int)) for p in outline_points}
    outline = (outline, outline_points, outline_keys, SegmentIndex(outline, 10.0))
    placed = {}
    claimed = set()
    unregistered = 0
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

    def on_printed_outline(p):
        return any(point_segment_distance(p, *outline[0][i]) <= 0.01 for i in outline[3].near(p - 0.01, p + 0.01))
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
    # The shared translation holds only when it puts every piece on the outline.
    shared = all(on_printed_outline(flat[i] + shared_t) for _, idx in piece_points for i in idx)
    ambiguous = []

    def settle(piece, points, idx, motion):
        R, t, landed = motion
        claimed.update(landed)
        # Refined: the mean offset from the moved points to the outline points they
        # landed on (the vote's bins are coarser than the drawing's rounding).
        matched = []
        for p0, p in zip(points, points @ R.T + t):
            near = outline[3].near(p - 0.01, p + 0.01)
            ends = [e for i in near for e in outline[0][i] if np.linalg.norm(e - p) <= 0.01]
            if ends:
                matched.append((p0, min(ends, key=lambda e: np.linalg.norm(e - p))))
        if len(matched) >= 2:
            # The rigid motion fitting them best (Procrustes, no reflection).
            P, Q = np.array([a for a, _ in matched]), np.array([b for _, b in matched])
            pc, qc = P.mean(axis=0), Q.mean(axis=0)
            H = (P - pc).T @ (Q - qc)
            angle = math.atan2(H[0, 1] - H[1, 0], H[0, 0] + H[1, 1])
            R = np.array([[math.cos(angle), -math.sin(angle)], [math.sin(angle), math.cos(angle)]])
            t = qc - pc @ R.T
        for i in members[piece]:
            placed[i] = flat[i] @ R.T + t
    for piece, (edges, idx) in enumerate(piece_points):
        points = flat[idx]
        edge_points = [(flat[a], flat[b]) for a, b in edges]
        if shared:
            motions = [(np.eye(2), shared_t, [tuple(np.round((p + shared_t) / 2e-3).astype(int)) for p in points])]
        else:
            # Where the piece's own name is printed, if it is.
            names = {face_groups[f] for f, face in enumerate(faces) if vt_piece[face[0][1]] == piece}
            name_at = [t["centre"] for t in texts if t["class"] == "piece" and t["text"] in names]
            diameter = float(np.linalg.norm(points.max(axis=0) - points.min(axis=0)))
            motions = []
            if len(name_at) == 1:
                motions = register(points, edge_points, outline, claimed, piece_folds[piece], fold_index,
                                   near=(name_at[0], diameter + 1.0))
            if not motions:
                motions = register(points, edge_points, outline, claimed, piece_folds[piece], fold_index)
        if not motions:
            unregistered += 1
            continue
        # Congruent pieces: the place where the piece's own name is printed inside it.
        names = {face_groups[f] for f, face in enumerate(faces) if vt_piece[face[0][1]] == piece}
        triangles = [flat[[c[1] for c in face]] for f, face in enumerate(faces)
                     if vt_piece[face[0][1]] == piece]
        name_points = [t["centre"] for t in texts if t["class"] == "piece" and t["text"] in names]

        def named_here(motion):
            R, t, _ = motion
            moved = np.array(triangles) @ R.T + t
            lo, hi = moved.min(axis=(0, 1)), moved.max(axis=(0, 1))
            for q in name_points:
                if np.all(q >= lo) and np.all(q <= hi):
                    if any(inside_triangle(q, *tri) for tri in moved):
                        return True
            return False
        named = [m for m in motions if named_here(m)]
        if named or len(motions) == 1:
            settle(piece, points, idx, (named or motions)[0])
        else:
            ambiguous.append((piece, points, idx, edges, motions))
    # Congruent pieces with no name printed, last: each where the seam IDs near its edges
    # agree with those near their partners already placed (for a maker, IDs are what tell
    # such pieces apart).
    seam_texts = [t for t in texts if t["class"] == "seam"]

    def ids_near(p, q):
        m = (p + q) / 2
        return {t["text"] for t in seam_texts if np.linalg.norm(t["centre"] - m) <= 4 * t["size"] + 2}
    for piece, points, idx, edges, motions in ambiguous:
        free = [m for m in motions if not claimed.intersection(m[2])] or motions

        def agreement(motion):
            R, t, _ = motion
            spot = {i: flat[i] @ R.T + t for i in idx}
            score = 0
            for a, b in edges:
                other = partner.get((a, b))
                if other and other[0] in placed and other[1] in placed:
                    score += bool(ids_near(spot[a], spot[b]) & ids_near(placed[other[0]], placed[other[1]]))
            return score
        settle(piece, points, idx, max(free, key=agreement))
    result = {"pieces": len(piece_of), "pieces_unregistered": unregistered, "glued_edge_pairs": len(pairs)}
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

    def sfind(e):
        while seam_parent[e] != e:
            seam_parent[e] = seam_parent[seam_parent[e]]
            e = seam_parent[e]
        return e
    for e in partner:
        n = next_edge.get(e[1])
        if n is None or n not in partner or partner[e] == n:
            continue
        # The next edge's partner must end where this edge's partner starts.
        if partner[n][1] == partner[e][0]:
            ra, rb = sfind(e), sfind(n)
            seam_parent[ra] = rb
    sides = defaultdict(list)
    for e in partner:
        sides[sfind(e)].append(e)
    seams = {}
    for root, edges in sides.items():
        other = sfind(partner[edges[0]])
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
