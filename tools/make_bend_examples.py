# Regenerates the procedural bend examples in examples/ (run from examples/).
# The closed strip's outline length is the curve length printed by
# `cargo run -p sheetform-bend --example curve_lengths -- examples/closed-strip.json`.
import json, math
def dump(name, d):
    open(name, 'w').write(json.dumps(d, indent=2) + "\n")
# Fig. 2/4: a bent rectangle (corner pieces stay planar)
dump("bent-rectangle.json", {
  "name": "bent rectangle (Bo & Wang Fig. 2/4)", "units": "mm",
  "outline": [[0,-60],[240,-60],[240,60],[0,60]],
  "regions": [{"name": "curl", "flat_start": [0,0], "flat_direction": [1,0],
    "curve": {"type": "bezier", "control_points": [[0,0,0],[70,0,10],[140,8,60],[160,12,120]]}}]})
# Fig. 12b: a sheet with a hole
hole = [[120 + 25*math.cos(2*math.pi*i/48), 25 + 25*math.sin(2*math.pi*i/48)] for i in range(48)]
dump("sheet-with-hole.json", {
  "name": "sheet with a hole (Bo & Wang Fig. 12b)", "units": "mm",
  "outline": [[0,-70],[300,-70],[300,70],[0,70]], "holes": [[[round(x,6), round(y,6)] for x,y in hole]],
  "regions": [{"name": "arch", "flat_start": [0,0], "flat_direction": [1,0],
    "curve": {"type": "bezier", "control_points": [[0,0,0],[60,0,60],[140,5,90],[215,10,40],[240,12,-10]]}}]})
# Fig. 14: a tube made by closing a sheet around a circle (exact circle geodesic)
R = 40.0
dump("tube.json", {
  "name": "tube (Bo & Wang Fig. 14)", "units": "mm",
  "outline": [[0,-50],[2*math.pi*R,-50],[2*math.pi*R,50],[0,50]],
  "regions": [{"name": "tube", "flat_start": [0,0], "flat_end": [2*math.pi*R, 0], "closed": True,
    "curve": {"type": "helix", "radius": R, "rise_per_radian": 0, "start_angle": 0, "end_angle": 2*math.pi}}]})
# Fig. 11: two curved pieces joined by a planar piece
dump("two-piece-composite.json", {
  "name": "two-piece composite (Bo & Wang Fig. 11)", "units": "mm",
  "outline": [[0,-50],[420,-50],[420,50],[0,50]],
  "regions": [
    {"name": "first bend", "flat_start": [0,0], "flat_direction": [1,0],
     "curve": {"type": "bezier", "control_points": [[0,0,0],[50,0,0],[100,0,30],[130,0,80]]}},
    {"name": "second bend", "flat_start": [260,0], "flat_direction": [1,0],
     "curve": {"type": "bezier", "control_points": [[0,0,0],[50,0,0],[90,0,-25],[120,5,-70]]}}]})
# Fig. 15: a desk: a planar top and four curved legs, cut from one cross-shaped sheet
T, W, Lg = 150.0, 50.0, 360.0   # half top size, half leg width, leg strip length
outline = [[-W,-T-Lg],[W,-T-Lg],[W,-T],[T,-T],[T,-W],[T+Lg,-W],[T+Lg,W],[T,W],[T,T],[W,T],[W,T+Lg],[-W,T+Lg],[-W,T],[-T,T],[-T,W],[-T-Lg,W],[-T-Lg,-W],[-T,-W],[-T,-T],[-W,-T]]
leg = [[0,0,0],[60,0,0],[95,0,-30],[95,0,-110],[90,0,-200],[130,0,-280]]  # S-curve: over the edge, down, flare
regions = []
for k,(sx,sy,dx,dy) in enumerate([(T,0,1,0),(0,T,0,1),(-T,0,-1,0),(0,-T,0,-1)]):
    regions.append({"name": f"leg {k+1}", "flat_start": [sx,sy], "flat_direction": [dx,dy],
      "up": [0,0,1], "curve": {"type": "bspline", "degree": 3, "control_points": leg}})
dump("desk.json", {"name": "desk (Bo & Wang Fig. 15)", "units": "mm", "outline": outline, "regions": regions})
# Fig. 12c: a closed strip: periodic saddle loop, mirror-symmetric at its start (torsion 0 there)
n = 12; pts = []; H = 12
for i in range(n):
    th = 2*math.pi*(i-1)/n
    pts.append([round(90*math.cos(th),9), round(60*math.sin(th),9), round(H*math.cos(2*th),9)])
dump("closed-strip.json", {"name": "closed strip (Bo & Wang Fig. 12c)", "units": "mm",
  "outline": [[0,-15],[473.614139600604,-15],[473.614139600604,15],[0,15]],
  "regions": [{"name": "loop", "flat_start": [0,0], "flat_direction": [1,0], "closed": True,
    "curve": {"type": "bspline", "degree": 4, "periodic": True, "control_points": pts}}]})

# Fig. 6: a textured sheet (the flat sheet is the texture domain). The texture is a
# labelled grid written as a PNG with the standard library only.
import struct, zlib
def png(path, w, h, pixel):
    raw = b"".join(b"\x00" + bytes(c for x in range(w) for c in pixel(x, y)) for y in range(h))
    chunk = lambda t, d: struct.pack(">I", len(d)) + t + d + struct.pack(">I", zlib.crc32(t + d) & 0xffffffff)
    open(path, "wb").write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
                            + chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))
def grid(x, y):
    # 480 x 240 px over a 240 x 120 mm sheet: 2 px per mm; lines every 10 mm, bold every 50.
    bold = x % 100 < 2 or y % 100 < 2
    thin = x % 20 == 0 or y % 20 == 0
    checker = ((x // 40) + (y // 40)) % 2
    base = (250, 244, 228) if checker else (236, 226, 200)
    return (40, 70, 140) if bold else (150, 160, 190) if thin else base
import os
os.makedirs("textures", exist_ok=True)
png("textures/grid-240x120mm.png", 480, 240, grid)
dump("textured-sheet.json", {
  "name": "textured sheet (Bo & Wang Fig. 6)", "units": "mm", "texture": "textures/grid-240x120mm.png",
  "outline": [[0,-60],[240,-60],[240,60],[0,60]],
  "regions": [{"name": "curl", "flat_start": [0,0], "flat_direction": [1,0],
    "curve": {"type": "bezier", "control_points": [[0,0,0],[70,0,10],[140,8,60],[160,12,120]]}}]})

# Fig. 13: a non-geodesic control curve: a band around a flat circular arc, bent along a
# helix whose curvature exceeds the arc's (the bent curve keeps the arc's curvature as its
# geodesic curvature).
def arc(r, a0, a1, n=24):
    return [[round(r*math.cos(math.radians(a0+(a1-a0)*i/n)),9), round(r*math.sin(math.radians(a0+(a1-a0)*i/n)),9)] for i in range(n+1)]
dump("arc-band.json", {
  "name": "band on a circular arc (Bo & Wang Fig. 13)", "units": "mm",
  "outline": arc(75, -95, -20) + arc(45, -20, -95),
  "regions": [{"name": "band", "flat_start": [0,-60], "flat_direction": [1,0],
    "flat_curve": {"type": "arc", "radius": 60, "turn": "left"},
    "curve": {"type": "helix", "radius": 40, "rise_per_radian": 10, "start_angle": -math.pi/2, "end_angle": 0.0}}]})
