// The sheetform web editor. Bend mode: every edit sends the whole scene to the server,
// which runs the same library pipeline as `sheetform bend` and answers with the bent
// sheet, its flat pattern and the report. An edit the server refuses (an inadmissible
// shape, an invalid scene) is shown and the last admissible scene is kept. Mesh mode: a
// mesh file (from the served directory, the disk, or dropped on the 3D view) goes to the
// server, which runs `sheetform check` and `sheetform flatten`'s pipelines and answers
// with its angle defects, the flattened model, its pattern and both reports. Slit mode:
// the sheet's lengths and strip count, and the control points of the leg and seat
// curves dragged in their planes; every change re-solves the strips (`sheetform slit`).
// FFD mode: a lattice control point dragged and released appends a deformation that
// moves it; the server restores developability (`sheetform ffd`) while the page shows
// its progress and can cancel it, then the restored panels and both colour maps.
// Photo mode: the annotation's curves drawn over its photograph; control points dragged,
// curves added, marked silhouette or boundary (or self-symmetric) or deleted; the
// symmetry frame, the mirror-symmetric points and the true-size segment dragged, the
// true size typed, the depth flipped; each change reconstructed (`sheetform photo`).

import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';

const $ = (id) => document.getElementById(id);

/**
 * Arrays of recent replies, by path and hash (issue 38: only what changed is sent). The
 * request names the newest array it holds at each path (`X-Sheetform-Held-Arrays`) and
 * the server leaves out those whose hash is unchanged (a bend drag keeps the rulings'
 * lists and the pieces; a new layout of a mesh keeps the model). A path keeps its
 * `HELD_PER_PATH` newest arrays, so that the reply to a request sent before the last
 * reply came still finds what it held.
 */
const heldArrays = new Map();
const HELD_PER_PATH = 4;

/** Editor state: the last admissible scene and what the server said of it. */
const state = {
  mode: 'bend', // 'bend', 'slit', 'ffd', 'photo' or 'mesh'
  fitChosen: false, // the pattern's scale was chosen with the checkbox (no automatic fit since)
  ffdController: null, // FFD mode: aborts the restoration under way
  ffdPending: null, // FFD mode: the newest scene waiting for the run under way to stop
  progress: [], // FFD mode: the progress lines of the last run
  cancellations: 0,
  sceneByMode: {}, // the last admissible scene of each scene mode
  pathByMode: {}, // the served file each scene mode's scene came from
  generation: 0, // bumped by a mode switch or a load: answers to older requests are dropped
  ffdRequested: null, // FFD mode: the scene of the run under way
  mesh: null, // mesh mode: { name, bytes (ArrayBuffer), path } of the loaded mesh
  highlight: null, // mesh mode: { key, pieces, seam } lit on the model and the pattern
  meshOptions: null, // mesh mode: the layout options of the last answered request
  path: null, // the scene file's path in the served directory, when it came from there
  scene: null, // the last admissible scene (an object; never mutated in place)
  reply: null, // the server's reply for `scene`
  undo: [], // earlier scenes (JSON text)
  redo: [],
  roundTrips: [], // ms from an edit's event to the redraw of its reply
  stages: [], // where each round trip's time went (ms)
  refusals: 0,
  boundaryStops: 0, // edits that stopped at the boundary of the admissible shapes
  answers: 0, // server answers (solved or refused), for tests and scripts to wait on
  inFlight: false,
  pending: null, // the newest edit waiting for the one in flight: { scene, started }
  requested: null, // the newest scene asked for and not answered yet (see latestScene)
  lastError: null,
  lastEdit: null, // what the library's editor said of the last edit
};

// ---------------------------------------------------------------- 3D view

const canvas = $('model-canvas');
const renderer = new THREE.WebGLRenderer({ canvas, antialias: false });
renderer.setPixelRatio(window.devicePixelRatio);
const view = new THREE.Scene();
view.background = new THREE.Color(0xf7f7f5);
const camera = new THREE.PerspectiveCamera(40, 1, 0.1, 1e6);
camera.up.set(0, 0, 1); // scenes are z-up
const controls = new OrbitControls(camera, canvas);
view.add(new THREE.HemisphereLight(0xffffff, 0x667788, 1.6));
const sun = new THREE.DirectionalLight(0xffffff, 1.4);
sun.position.set(1, -2, 3);
view.add(sun);

const sheetMaterial = new THREE.MeshStandardMaterial({
  color: 0xe9d8b4, side: THREE.DoubleSide, roughness: 0.85, polygonOffset: true,
  polygonOffsetFactor: 1, polygonOffsetUnits: 1,
});
// Mesh mode colours each triangle (its piece, or the angle defect at its vertices).
const colouredMaterial = new THREE.MeshStandardMaterial({
  vertexColors: true, side: THREE.DoubleSide, roughness: 0.85, polygonOffset: true,
  polygonOffsetFactor: 1, polygonOffsetUnits: 1,
});
const sheet = new THREE.Mesh(new THREE.BufferGeometry(), sheetMaterial);
const rulings = new THREE.LineSegments(new THREE.BufferGeometry(), new THREE.LineBasicMaterial({ color: 0x8a7a5a }));
const handles = new THREE.Group();
const handleLines = new THREE.Group();
// Everything drawn of a design, in its own frame: bend scenes are z-up as the view,
// slit scenes y-up (the paper's), turned upright by a quarter turn about x.
const content = new THREE.Group();
// Bend mode: the curve of regression where it comes near the sheet (red).
const regression = new THREE.Group();
// Bend mode: the piece under the pointer (a curved region or a planar part), lit over
// the sheet on the model as on the pattern.
const litPiece = new THREE.Mesh(new THREE.BufferGeometry(), new THREE.MeshBasicMaterial({
  color: 0xff7a00, transparent: true, opacity: 0.45, side: THREE.DoubleSide, depthWrite: false,
}));
litPiece.renderOrder = 1;
content.add(sheet, rulings, handles, handleLines, regression, litPiece);
view.add(content);
const handleGeometry = new THREE.SphereGeometry(1, 20, 14);
// Handles and the control polygon are drawn over the sheet, never hidden behind it.
const handleMaterial = new THREE.MeshBasicMaterial({ color: 0xe8731a, depthTest: false });
const handleActive = new THREE.MeshBasicMaterial({ color: 0xc0392b, depthTest: false });
const normalMaterial = new THREE.MeshBasicMaterial({ color: 0x2e8b57, depthTest: false });
const seatMaterial = new THREE.MeshBasicMaterial({ color: 0x2b5d8a, depthTest: false });
// Slit anchors: the ridge-line ends that can be anchored (grey, hidden behind the sheet)
// and the anchors (yellow).
const anchorableMaterial = new THREE.MeshBasicMaterial({ color: 0x6b6b6b });
const anchorMaterial = new THREE.MeshBasicMaterial({ color: 0xf1c40f, depthTest: false });
const latticeMaterial = new THREE.MeshBasicMaterial({ color: 0x7a4fa0, depthTest: false });
const regressionMaterial = new THREE.LineBasicMaterial({ color: 0xd62728 });
let handleRadius = 3;
let framed = false;

function resize() {
  const { clientWidth: w, clientHeight: h } = canvas.parentElement;
  renderer.setSize(w, h, false);
  camera.aspect = w / Math.max(h, 1);
  camera.updateProjectionMatrix();
}
new ResizeObserver(() => { resize(); render(); }).observe(canvas.parentElement);

function render() {
  renderer.render(view, camera);
}
controls.addEventListener('change', render);

/** The curves whose control points can be dragged: [{ region, points }]. */
function draggableCurves(scene) {
  return (scene.regions || [])
    .map((region, index) => ({ region: index, points: region.curve && region.curve.control_points }))
    .filter((c) => Array.isArray(c.points));
}

/** The principal normal of a Bézier curve at its start (`atEnd` false) or end, unit. */
function endNormal(points, atEnd) {
  const p = (atEnd ? [...points].reverse() : points).slice(0, 3).map((q) => new THREE.Vector3(...q));
  const d = p[1].clone().sub(p[0]);
  const second = p[2].clone().sub(p[1].clone().multiplyScalar(2)).add(p[0]);
  return d.clone().cross(second).cross(d).normalize();
}

/** A helix's handles (bend mode), in its curve's coordinates (Bo & Wang Fig. 14: the
 * helix `center + (r cos θ, r sin θ, c θ)`): `radius` at its end, `θ = end_angle`, moved
 * along the radial line there; `pitch` on its axis at the height of the end farther
 * from `θ = 0` (none when both ends are at 0), moved along the axis: `c` is that
 * height over the angle. Each with its line (`origin`, `direction`). */
function helixHandles(curve) {
  const [cx, cy, cz] = curve.center || [0, 0, 0];
  const r = curve.radius;
  const c = curve.rise_per_radian || 0;
  const start = curve.start_angle || 0;
  const end = curve.end_angle;
  const handles = [{
    what: 'radius',
    position: new THREE.Vector3(cx + r * Math.cos(end), cy + r * Math.sin(end), cz + c * end),
    origin: new THREE.Vector3(cx, cy, cz + c * end),
    direction: new THREE.Vector3(Math.cos(end), Math.sin(end), 0),
  }];
  const angle = Math.abs(end) >= Math.abs(start) ? end : start;
  if (angle !== 0) {
    handles.push({
      what: 'pitch', angle,
      position: new THREE.Vector3(cx, cy, cz + c * angle),
      origin: new THREE.Vector3(cx, cy, cz),
      direction: new THREE.Vector3(0, 0, 1),
    });
  }
  return handles;
}

/** The set_helix edit a helix handle dragged to `onCurve` (curve coordinates) asks for. */
function helixEdit(region, handle, onCurve) {
  const curve = state.scene.regions[region].curve;
  const [cx, cy, cz] = curve.center || [0, 0, 0];
  // Signed along the spoke: dragged through the axis, the radius goes to 0 and below
  // (refused at the boundary), not up again on the other side.
  if (handle.what === 'radius') return { kind: 'set_helix', region, radius: (onCurve.x - cx) * handle.direction.x + (onCurve.y - cy) * handle.direction.y };
  return { kind: 'set_helix', region, rise_per_radian: (onCurve.z - cz) / handle.angle };
}

function dragMode() {
  return $('drag-mode').value;
}

/** Region `region`'s curve coordinates → the model's frame (Bo & Wang §4.2: each region
 * after the first is placed by the pieces it is attached to), from the last reply. */
function regionMatrix(region) {
  const frame = state.reply && state.reply.region_frames && state.reply.region_frames[region];
  const m = new THREE.Matrix4();
  if (!frame) return m;
  const [r0, r1, r2] = frame.rotation;
  const t = frame.translation;
  return m.set(r0[0], r0[1], r0[2], t[0], r1[0], r1[1], r1[2], t[1], r2[0], r2[1], r2[2], t[2], 0, 0, 0, 1);
}

/** The plane of a planar control polygon (curve coordinates): `{ normal, point }`, or
 * null when the points are collinear or not in one plane (within 1e-6 of its size). */
function controlPlane(points) {
  const p = points.map((q) => new THREE.Vector3(...q));
  // Three points are always in a plane: a curve of degree 2 is not held in one.
  if (p.length < 4) return null;
  const far = p.reduce((a, q) => (q.distanceTo(p[0]) > a.distanceTo(p[0]) ? q : a), p[0]);
  const size = far.distanceTo(p[0]);
  if (size === 0) return null;
  const line = new THREE.Line3(p[0], far);
  const off = p.reduce((a, q) => (line.closestPointToPoint(q, false, new THREE.Vector3()).distanceTo(q)
    > line.closestPointToPoint(a, false, new THREE.Vector3()).distanceTo(a) ? q : a), p[0]);
  const normal = far.clone().sub(p[0]).cross(off.clone().sub(p[0]));
  if (normal.length() <= 1e-9 * size * size) return null;
  normal.normalize();
  const planar = p.every((q) => Math.abs(q.clone().sub(p[0]).dot(normal)) <= 1e-6 * size);
  return planar ? { normal, point: p[0] } : null;
}

/** The drag locks of the 3D view (as in DCC tools: X, Y, Z keys lock an axis, with
 * Shift the plane across it); "auto" keeps a planar curve's points in its plane. */
const LOCKS = {
  x: { axis: [1, 0, 0] }, y: { axis: [0, 1, 0] }, z: { axis: [0, 0, 1] },
  yz: { normal: [1, 0, 0] }, zx: { normal: [0, 1, 0] }, xy: { normal: [0, 0, 1] },
};

function drawHandles(scene) {
  handles.clear();
  handleLines.clear();
  if (state.mode === 'slit') {
    drawSlitHandles(scene);
    return;
  }
  if (state.mode === 'ffd') {
    drawLattice(state.reply && state.reply.lattice);
    return;
  }
  if (state.mode === 'photo') {
    drawPhotoEditor(scene);
    return;
  }
  const ends = dragMode() === 'ends';
  for (const { region, points } of draggableCurves(scene)) {
    // The length-preserving drag and the end handles edit Bézier curves (§4.1.2–3).
    if (dragMode() !== 'move' && scene.regions[region].curve.type !== 'bezier') continue;
    const frame = regionMatrix(region);
    const placed = (q) => new THREE.Vector3(...q).applyMatrix4(frame);
    points.forEach((p, index) => {
      const isEnd = index === 0 || index === points.length - 1;
      if (ends && !isEnd) return;
      const ball = new THREE.Mesh(handleGeometry, handleMaterial);
      ball.position.copy(placed(p));
      ball.scale.setScalar(handleRadius);
      ball.userData = ends ? { region, end: index === 0 ? 'start' : 'end', what: 'position', index } : { region, index };
      ball.renderOrder = 2;
      handles.add(ball);
    });
    if (ends && points.length >= 4) {
      for (const atEnd of [false, true]) {
        const origin = placed(points[atEnd ? points.length - 1 : 0]);
        const tip = origin.clone().add(endNormal(points, atEnd).transformDirection(frame).multiplyScalar(handleRadius * 10));
        const ball = new THREE.Mesh(handleGeometry, normalMaterial);
        ball.position.copy(tip);
        ball.scale.setScalar(handleRadius * 0.8);
        ball.userData = { region, end: atEnd ? 'end' : 'start', what: 'normal' };
        ball.renderOrder = 2;
        handles.add(ball);
        handleLines.add(new THREE.Line(new THREE.BufferGeometry().setFromPoints([origin, tip]), new THREE.LineBasicMaterial({ color: 0x2e8b57, depthTest: false })));
      }
    }
    const polygon = new THREE.BufferGeometry().setFromPoints(points.map(placed));
    handleLines.add(new THREE.Line(polygon, new THREE.LineDashedMaterial({ color: 0xe8731a, dashSize: 4, gapSize: 3, depthTest: false })));
    handleLines.children.at(-1).computeLineDistances();
  }
  // A helix's radius (orange, on the spoke from its axis to its end) and pitch (green,
  // on its axis): dragged along their lines, each an edit of that parameter alone.
  if (dragMode() !== 'move') return;
  (scene.regions || []).forEach((region, index) => {
    if (!region.curve || region.curve.type !== 'helix') return;
    const frame = regionMatrix(index);
    for (const handle of helixHandles(region.curve)) {
      const ball = new THREE.Mesh(handleGeometry, handle.what === 'radius' ? handleMaterial : normalMaterial);
      ball.position.copy(handle.position.clone().applyMatrix4(frame));
      ball.scale.setScalar(handleRadius);
      ball.userData = { region: index, helix: handle.what };
      ball.renderOrder = 2;
      handles.add(ball);
      const spoke = [handle.origin, handle.position].map((q) => q.clone().applyMatrix4(frame));
      handleLines.add(new THREE.Line(new THREE.BufferGeometry().setFromPoints(spoke), new THREE.LineDashedMaterial({ color: handle.what === 'radius' ? 0xe8731a : 0x2e8b57, dashSize: 4, gapSize: 3, depthTest: false })));
      handleLines.children.at(-1).computeLineDistances();
    }
  });
}

/** A slit scene's draggable points: the leg curve at the sheet's front edge (`[x, y]`
 * at z = 0) and the seat curve in the symmetry plane (`[z, y]` at x = 0), in the
 * scene's y-up frame. */
function slitCurves(scene) {
  const curves = [];
  if (scene.leg_curve) curves.push({ curve: 'leg_curve', points: scene.leg_curve.control_points.map(([x, y]) => [x, y, 0]) });
  if (scene.seat_curve) curves.push({ curve: 'seat_curve', points: scene.seat_curve.control_points.map(([z, y]) => [0, y, z]) });
  return curves;
}

/** The deformed lattice: a handle per control point and its lines along i, j and k. */
function drawLattice(lattice) {
  if (!lattice) return;
  const [nu, nv, nw] = lattice.counts;
  const p = lattice.control_points;
  const at = (i, j, k) => 3 * (i + nu * (j + nv * k));
  const segments = [];
  for (let k = 0; k < nw; k++) {
    for (let j = 0; j < nv; j++) {
      for (let i = 0; i < nu; i++) {
        const ball = new THREE.Mesh(handleGeometry, latticeMaterial);
        ball.position.set(p[at(i, j, k)], p[at(i, j, k) + 1], p[at(i, j, k) + 2]);
        ball.scale.setScalar(handleRadius * 0.7);
        ball.userData = { lattice: [i, j, k] };
        ball.renderOrder = 2;
        handles.add(ball);
        for (const [a, b, c] of [[i + 1, j, k], [i, j + 1, k], [i, j, k + 1]]) {
          if (a < nu && b < nv && c < nw) segments.push(...p.slice(at(i, j, k), at(i, j, k) + 3), ...p.slice(at(a, b, c), at(a, b, c) + 3));
        }
      }
    }
  }
  const lines = new THREE.BufferGeometry();
  lines.setAttribute('position', new THREE.Float32BufferAttribute(segments, 3));
  handleLines.add(new THREE.LineSegments(lines, new THREE.LineBasicMaterial({ color: 0x7a4fa0, transparent: true, opacity: 0.45, depthTest: false })));
}

function drawSlitHandles(scene) {
  // Anchors (Tsuruta et al. Fig. 12): each ridge-line end a small grey point to click
  // (an anchor at its place), each anchor a yellow ball to drag (shift-click removes it).
  const anchored = new Set((scene.anchors || []).map((a) => `${a.strip}/${a.ridge}/${a.side}`));
  for (const point of (state.reply && state.reply.anchorable_points) || []) {
    if (anchored.has(`${point.strip}/${point.ridge}/${point.side}`)) continue;
    const dot = new THREE.Mesh(handleGeometry, anchorableMaterial);
    dot.position.set(...point.position);
    dot.scale.setScalar(handleRadius * 0.45);
    dot.userData = { anchorable: point };
    handles.add(dot);
  }
  (scene.anchors || []).forEach((anchor, index) => {
    const ball = new THREE.Mesh(handleGeometry, anchorMaterial);
    ball.position.set(...anchor.position);
    ball.scale.setScalar(handleRadius * 1.1);
    ball.userData = { anchor: index };
    ball.renderOrder = 3;
    handles.add(ball);
  });
  for (const { curve, points } of slitCurves(scene)) {
    const material = curve === 'leg_curve' ? handleMaterial : seatMaterial;
    points.forEach((p, index) => {
      const ball = new THREE.Mesh(handleGeometry, material);
      ball.position.set(...p);
      ball.scale.setScalar(handleRadius);
      ball.userData = { curve, index };
      ball.renderOrder = 2;
      handles.add(ball);
    });
    const polygon = new THREE.BufferGeometry().setFromPoints(points.map((p) => new THREE.Vector3(...p)));
    const line = new THREE.Line(polygon, new THREE.LineDashedMaterial({ color: material.color, dashSize: 4, gapSize: 3, depthTest: false }));
    line.computeLineDistances();
    handleLines.add(line);
  }
}

/** The curve of regression's stretches near the sheet (bend mode), as red polylines. */
function drawRegression(curves) {
  for (const line of regression.children) line.geometry.dispose();
  regression.clear();
  for (const curve of curves) {
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute('position', new THREE.Float32BufferAttribute(curve, 3));
    regression.add(new THREE.Line(geometry, regressionMaterial));
  }
}

function drawModel(model, angleDefects) {
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute('position', new THREE.Float32BufferAttribute(model.positions, 3));
  geometry.setIndex(ArrayBuffer.isView(model.triangles) ? new THREE.BufferAttribute(model.triangles, 1) : model.triangles);
  geometry.computeVertexNormals();
  // Bend mode's developability colour map: the angle defect at each vertex.
  const coloured = state.mode === 'bend' && angleDefects && $('bend-view').value === 'defect';
  if (coloured) {
    const colour = new Float32Array(3 * angleDefects.length);
    angleDefects.forEach((g, v) => {
      const c = defectColour(g);
      colour.set([c.r, c.g, c.b], 3 * v);
    });
    geometry.setAttribute('color', new THREE.BufferAttribute(colour, 3));
  }
  sheet.geometry.dispose();
  sheet.geometry = geometry;
  // The rulings as line segments, written straight into the attribute's array.
  const p = model.positions;
  let count = 0;
  for (const line of model.rulings) count += Math.max(0, line.length - 1);
  const segments = new Float32Array(6 * count);
  let at = 0;
  for (const line of model.rulings) {
    for (let k = 0; k + 1 < line.length; k++) {
      for (const v of [line[k], line[k + 1]]) {
        segments[at++] = p[3 * v];
        segments[at++] = p[3 * v + 1];
        segments[at++] = p[3 * v + 2];
      }
    }
  }
  const lines = new THREE.BufferGeometry();
  lines.setAttribute('position', new THREE.BufferAttribute(segments, 3));
  rulings.geometry.dispose();
  rulings.geometry = lines;
  sheet.material = coloured ? colouredMaterial : sheetMaterial;
  frame(geometry);
}

/** Points the camera at `geometry` once per loaded scene or mesh. */
function frame(geometry) {
  if (!framed) {
    const yUp = state.mode === 'slit' || (state.mode === 'ffd' && state.scene && state.scene.up_axis === 'y');
    content.rotation.x = yUp ? Math.PI / 2 : 0;
    content.updateMatrixWorld(true);
    geometry.computeBoundingSphere();
    const { radius } = geometry.boundingSphere;
    const center = content.localToWorld(geometry.boundingSphere.center.clone());
    controls.target.copy(center);
    camera.position.copy(center).add(new THREE.Vector3(0.9, -1.6, 1.1).multiplyScalar(radius * 1.6));
    camera.near = radius / 100;
    camera.far = radius * 100;
    camera.updateProjectionMatrix();
    controls.update();
    handleRadius = radius / 45;
    framed = true;
  }
}

// ---------------------------------------------------------------- mesh mode view

/** A colour per piece: evenly spaced hues, light enough to shade. */
function pieceColour(piece) {
  return new THREE.Color().setHSL(((piece * 0.618034) % 1 + 1) % 1, 0.55, 0.68);
}

/** The colour of an angle defect `g` (rad): grey when developable (|g| ≤ 1e-6 rad),
 * then yellow to red on a log scale up to 0.1 rad. */
function defectColour(g) {
  const t = Math.min(1, Math.max(0, (Math.log10(Math.abs(g) + 1e-300) + 6) / 5));
  return Math.abs(g) <= 1e-6 ? new THREE.Color(0xd9d6cf) : new THREE.Color().setHSL(0.15 * (1 - t), 0.85, 0.55);
}

/** Mesh mode: the flattened model coloured by piece, or the input by angle defect. */
function drawMeshModel(reply) {
  showColouredGeometry($('colour').value === 'defect'
    ? colouredGeometry(reply.input, (v) => defectColour(reply.input.angle_defects_rad[v]))
    : colouredGeometry(reply.model, (_, t) => pieceColour(reply.model.face_pieces[t])));
}

/** Shows a vertex-coloured geometry in place of the sheet, without rulings or handles. */
function showColouredGeometry(geometry) {
  sheet.geometry.dispose();
  sheet.geometry = geometry;
  sheet.material = colouredMaterial;
  rulings.geometry.dispose();
  rulings.geometry = new THREE.BufferGeometry();
  handles.clear();
  handleLines.clear();
  frame(geometry);
}

/** A triangle soup of `mesh` ({positions, triangles}) with a colour per corner. */
function colouredGeometry(mesh, colourOf) {
  const { positions, triangles } = mesh;
  const position = new Float32Array(triangles.length * 3);
  const colour = new Float32Array(triangles.length * 3);
  for (let k = 0; k < triangles.length; k++) {
    const v = triangles[k];
    position.set([positions[3 * v], positions[3 * v + 1], positions[3 * v + 2]], 3 * k);
    const c = colourOf(v, Math.floor(k / 3));
    colour.set([c.r, c.g, c.b], 3 * k);
  }
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute('position', new THREE.BufferAttribute(position, 3));
  geometry.setAttribute('color', new THREE.BufferAttribute(colour, 3));
  geometry.computeVertexNormals();
  return geometry;
}

/** The FFD colour maps' scale (as the CLI's): blue at 1e-8 rad (developable) to red at
 * the largest defect before restoration, logarithmic. */
function ffdDefectColour(g, top) {
  const floor = 1e-8;
  const span = Math.max(Math.log10(Math.max(top, floor * 10) / floor), 1e-9);
  const t = Math.min(1, Math.max(0, Math.log10(Math.max(Math.abs(g), floor) / floor) / span));
  return new THREE.Color().setHSL(0.66 * (1 - t), 0.75, 0.55);
}

/** FFD mode: the restored or plain panels coloured by angle defect, or by panel. */
function drawFfdModel(reply) {
  const view = $('ffd-view').value;
  // (A reduce, not a spread: a 100k-vertex model would overflow the argument list.)
  const top = reply.plain.angle_defects_rad.reduce((m, g) => Math.max(m, Math.abs(g)), 1e-300);
  const shown = reply[view === 'before' ? 'plain' : 'restored'];
  showColouredGeometry(view === 'pieces'
    ? colouredGeometry(reply.model, (_, t) => pieceColour(reply.model.face_pieces[t]))
    : colouredGeometry(shown, (v) => ffdDefectColour(shown.angle_defects_rad[v], top)));
  drawLattice(reply.lattice);
}

// ---------------------------------------------------------------- photo mode view

const SVG = 'http://www.w3.org/2000/svg';
const photoSvg = $('photo-svg');
const KIND_COLOURS = { silhouette: '#2b5d8a', boundary: '#c0392b' };
// `draft`: the annotation was started from a photograph in the editor. Its steps are
// kept whether or not they reconstruct (the reason shown), so it can be traced curve by
// curve and corrected freely, and undo/redo move through those steps; an annotation
// opened from a file keeps its last admissible state instead.
const photo = { drag: null, working: null, adding: null, draft: false };

function svgElement(name, attributes, parent) {
  const element = document.createElementNS(SVG, name);
  for (const [key, value] of Object.entries(attributes)) element.setAttribute(key, value);
  parent.append(element);
  return element;
}

/** The SVG path of a piecewise cubic Bézier (`3k + 1` points). */
function bezierPath(points) {
  let d = `M ${points[0][0]} ${points[0][1]}`;
  for (let j = 1; j + 2 < points.length; j += 3) {
    d += ` C ${points[j].join(' ')} ${points[j + 1].join(' ')} ${points[j + 2].join(' ')}`;
  }
  return d;
}

/** The annotation over its photograph: curves by kind, their control points, the
 * symmetry frame and points, the true-size segment; and the list of curves. */
function drawPhotoEditor(scene) {
  const { width, height, path } = scene.image;
  photoSvg.setAttribute('viewBox', `0 0 ${width} ${height}`);
  photoSvg.innerHTML = '';
  const href = `/api/files/${[sceneDirectory(), path].filter(Boolean).join('/').split('/').map(encodeURIComponent).join('/')}`;
  svgElement('image', { href, x: 0, y: 0, width, height }, photoSvg);
  const unit = Math.max(width, height) / 400;
  const marks = svgElement('g', {}, photoSvg);
  // The symmetry frame (cyan), the mirror-symmetric points (red squares) and the
  // true-size segment (green), each end a handle to drag (`data-mark`: which point).
  const handle = (mark, [x, y], colour, square = false) => {
    const size = 2.2 * unit;
    const attributes = { fill: colour, stroke: '#fff', 'stroke-width': unit * 0.4, 'data-mark': mark, class: 'mark' };
    if (square) svgElement('rect', { x: x - size, y: y - size, width: 2 * size, height: 2 * size, ...attributes }, marks);
    else svgElement('circle', { cx: x, cy: y, r: size, ...attributes }, marks);
  };
  const symmetry = scene.symmetry;
  if (symmetry) {
    (symmetry.frame || []).forEach(([[x1, y1], [x2, y2]], s) => {
      svgElement('line', { x1, y1, x2, y2, stroke: '#17a2b8', 'stroke-width': unit, 'pointer-events': 'none' }, marks);
      handle(`symmetry.frame.${s}.0`, [x1, y1], '#17a2b8');
      handle(`symmetry.frame.${s}.1`, [x2, y2], '#17a2b8');
    });
    (symmetry.points || []).forEach((point, k) => handle(`symmetry.points.${k}`, point, '#e74c3c', true));
    $('flip-depth').checked = Boolean(symmetry.flip_depth);
  }
  $('back-side').value = scene.back_side || 'visible';
  if (scene.true_size) {
    const { from: [x1, y1], to: [x2, y2] } = scene.true_size;
    svgElement('line', { x1, y1, x2, y2, stroke: '#27ae60', 'stroke-width': unit * 0.7, 'stroke-dasharray': `${4 * unit} ${2 * unit}`, 'pointer-events': 'none' }, marks);
    handle('true_size.from', [x1, y1], '#27ae60');
    handle('true_size.to', [x2, y2], '#27ae60');
    if (document.activeElement !== $('true-size')) $('true-size').value = scene.true_size.length;
    $('true-size-unit').textContent = scene.units || 'mm';
  }
  scene.curves.forEach((curve, c) => {
    const colour = KIND_COLOURS[curve.kind] || '#555';
    const group = svgElement('g', { 'data-curve': c }, photoSvg);
    svgElement('polyline', {
      points: curve.control_points.map((p) => p.join(',')).join(' '), fill: 'none', stroke: colour,
      'stroke-width': unit * 0.4, 'stroke-dasharray': `${2 * unit} ${2 * unit}`, opacity: 0.6, 'pointer-events': 'none',
    }, group);
    svgElement('path', { d: bezierPath(curve.control_points), fill: 'none', stroke: colour, 'stroke-width': unit * 1.2, 'pointer-events': 'none' }, group);
    curve.control_points.forEach(([x, y], index) => {
      svgElement('circle', {
        cx: x, cy: y, r: (index % 3 === 0 ? 2.4 : 1.8) * unit, fill: index % 3 === 0 ? colour : '#fff', stroke: colour,
        'stroke-width': unit * 0.5, 'data-curve': c, 'data-index': index,
      }, group);
    });
  });
  // The marks' handles over the curves (a true-size end lies on a curve).
  photoSvg.append(marks);
  for (const point of photo.adding || []) {
    svgElement('circle', { cx: point[0], cy: point[1], r: 2 * unit, fill: '#f39c12' }, photoSvg);
  }
  drawCurveList(scene);
}

function drawCurveList(scene) {
  const list = $('curve-list');
  list.innerHTML = '<strong>curves</strong>';
  const selfSymmetric = new Set(scene.self_symmetric_curves || []);
  scene.curves.forEach((curve, c) => {
    const row = document.createElement('div');
    row.dataset.curve = curve.name;
    row.innerHTML = `<span style="color:${KIND_COLOURS[curve.kind] || '#555'}">●</span> <span class="name"></span>
      <select class="kind"><option value="boundary">boundary</option><option value="silhouette">silhouette</option></select>
      <label title="The curve is its own mirror image"><input type="checkbox" class="self"> sym.</label>
      <button class="delete" title="Delete the curve">×</button>`;
    row.querySelector('.name').textContent = curve.name;
    row.querySelector('.kind').value = curve.kind;
    row.querySelector('.self').checked = selfSymmetric.has(curve.name);
    row.querySelector('.kind').addEventListener('change', (event) => {
      const next = structuredClone(latestScene());
      next.curves[c].kind = event.target.value;
      commit(next);
    });
    row.querySelector('.self').addEventListener('change', (event) => {
      const next = structuredClone(latestScene());
      const names = new Set(next.self_symmetric_curves || []);
      if (event.target.checked) names.add(curve.name); else names.delete(curve.name);
      next.self_symmetric_curves = [...names];
      commit(next);
    });
    row.querySelector('.delete').addEventListener('click', () => {
      const next = structuredClone(latestScene());
      next.curves.splice(c, 1);
      const keep = (name) => name !== curve.name;
      if (next.self_symmetric_curves) next.self_symmetric_curves = next.self_symmetric_curves.filter(keep);
      if (next.symmetric_curves) next.symmetric_curves = next.symmetric_curves.filter((pair) => pair.every(keep));
      commit(next);
    });
    list.append(row);
  });
}

/** Sets the field at the path `keys` (e.g. `['true_size', 'to']`) of `object`. */
function setAt(object, keys, value) {
  keys.slice(0, -1).reduce((inner, key) => inner[key], object)[keys.at(-1)] = value;
}

/** A pointer event's position in the photograph's pixels. */
function photoPoint(event) {
  const point = new DOMPoint(event.clientX, event.clientY).matrixTransform(photoSvg.getScreenCTM().inverse());
  return [point.x, point.y];
}

photoSvg.addEventListener('pointerdown', (event) => {
  if (state.mode !== 'photo' || !state.scene || event.button !== 0) return;
  if (photo.adding) {
    photo.adding.push(photoPoint(event));
    if (photo.adding.length === 4) {
      const next = structuredClone(latestScene());
      const names = new Set(next.curves.map((c) => c.name));
      let n = next.curves.length + 1;
      while (names.has(`curve-${n}`)) n += 1;
      next.curves.push({ name: `curve-${n}`, kind: $('new-kind').value, control_points: photo.adding });
      photo.adding = null;
      photoSvg.classList.remove('adding');
      commit(next);
    } else {
      drawPhotoEditor(state.scene);
    }
    return;
  }
  const target = event.target;
  if (target.dataset.mark !== undefined) {
    // A symmetry or true-size point: `symmetry.frame.S.E`, `symmetry.points.K`,
    // `true_size.from` or `true_size.to`, a path into the annotation.
    photo.drag = { mark: target.dataset.mark.split('.'), moved: false };
  } else if (target.tagName === 'circle' && target.dataset.curve !== undefined) {
    photo.drag = { curve: Number(target.dataset.curve), index: Number(target.dataset.index), moved: false };
  } else {
    return;
  }
  photo.working = structuredClone(latestScene());
  photoSvg.setPointerCapture(event.pointerId);
});

photoSvg.addEventListener('pointermove', (event) => {
  if (!photo.drag) return;
  if (photo.drag.mark) {
    setAt(photo.working, photo.drag.mark, photoPoint(event));
  } else {
    photo.working.curves[photo.drag.curve].control_points[photo.drag.index] = photoPoint(event);
  }
  photo.drag.moved = true;
  drawPhotoEditor(photo.working);
});

function endPhotoDrag(event) {
  if (!photo.drag) return;
  const { moved } = photo.drag;
  photo.drag = null;
  if (photoSvg.hasPointerCapture(event.pointerId)) photoSvg.releasePointerCapture(event.pointerId);
  // The reconstruction runs on release; a refusal redraws the last admissible annotation.
  if (moved) commit(photo.working);
}
photoSvg.addEventListener('pointerup', endPhotoDrag);
photoSvg.addEventListener('pointercancel', endPhotoDrag);

$('add-curve').addEventListener('click', () => {
  photo.adding = [];
  photoSvg.classList.add('adding');
  showStatus('busy', 'click the new curve\'s four control points on the photo');
});
/** A new annotation on the photograph `path` (`width` × `height` pixels): no curves
 * yet, the symmetry frame, its mirror-symmetric points and the true-size segment placed
 * in the middle of the photograph, to be dragged where they belong. */
function newAnnotation(path, width, height) {
  const at = (x, y) => [Math.round(x * width * 100) / 100, Math.round(y * height * 100) / 100];
  return {
    name: path.split('/').at(-1).replace(/\.[^.]*$/, ''),
    units: 'mm',
    image: { path, width, height },
    curves: [],
    symmetry: { frame: [[at(0.5, 0.7), at(0.5, 0.3)], [at(0.5, 0.3), at(0.35, 0.55)]], points: [at(0.3, 0.4), at(0.7, 0.42)] },
    true_size: { from: at(0.3, 0.62), to: at(0.7, 0.62), length: 100 },
  };
}

/** Opens the chooser dialog `dialog` with the served files of `kind` (`/api/files`'s
 * `photos` or `meshes`) in its list `select`; its button `start` only when there is one. */
async function openChooser(dialog, select, start, kind) {
  const response = await fetch('/api/files');
  const files = (response.ok && (await response.json())) || {};
  const names = files[kind] || [];
  fillSelect($(select), names, Boolean(files.truncated && files.truncated[kind]));
  $(start).disabled = names.length === 0;
  // Esc closes it without changing returnValue: the last answer must not start again.
  $(dialog).returnValue = '';
  $(dialog).showModal();
}

$('new-annotation').addEventListener('click', () => {
  $('photo-file').value = '';
  openChooser('photo-chooser', 'photo-choice', 'photo-chosen', 'photos');
});
$('photo-chooser').addEventListener('close', () => {
  if ($('photo-chooser').returnValue === 'served' && $('photo-choice').value) startAnnotation($('photo-choice').value);
});
$('photo-file').addEventListener('change', (event) => {
  const file = event.target.files[0];
  $('photo-chooser').close('file');
  if (file) annotatePhotoFile(file);
});

/** A photograph from disk (chosen or dropped): kept in the served directory (the
 * server picks a free name under `photos/`), then annotated. */
async function annotatePhotoFile(file) {
  showStatus('busy', `keeping ${file.name} in the served directory…`);
  const response = await fetch(`/api/photos/${encodeURIComponent(file.name)}`, { method: 'PUT', body: file });
  const body = await response.json();
  if (!response.ok) {
    showStatus('error', `${file.name}: ${body.error.message}`);
    return;
  }
  await startAnnotation(body.path);
}

/** A new annotation on the photograph `path` (in the served directory). */
async function startAnnotation(path) {
  const image = new Image();
  image.src = `/api/files/${path.split('/').map(encodeURIComponent).join('/')}`;
  try {
    await image.decode();
  } catch {
    showStatus('error', `${path} is not a PNG or JPEG photograph in the served directory`);
    return;
  }
  if (state.mode !== 'photo') setMode('photo');
  state.generation += 1;
  heldArrays.clear();
  state.pending = null;
  state.requested = null;
  state.path = null;
  state.pathByMode.photo = null;
  state.undo = [];
  state.redo = [];
  updateHistoryButtons();
  photo.draft = true;
  photo.adding = null;
  state.scene = newAnnotation(path, image.naturalWidth, image.naturalHeight);
  state.sceneByMode.photo = state.scene;
  state.reply = null;
  // Nothing reconstructed yet: no model, no pattern (not the last annotation's).
  sheet.geometry.dispose();
  sheet.geometry = new THREE.BufferGeometry();
  rulings.geometry.dispose();
  rulings.geometry = new THREE.BufferGeometry();
  framed = false;
  drawPattern('');
  $('photo-pane').value = 'photo';
  $('photo-editor').hidden = false;
  drawPhotoEditor(state.scene);
  showStatus('busy', 'a new annotation: add the curves (Add curve, four clicks each), then drag the symmetry marks (cyan frame, red points) and the true-size segment (green) into place');
}

$('true-size').addEventListener('change', (event) => {
  if (state.mode !== 'photo' || !state.scene) return;
  const length = Number(event.target.value);
  if (!(Number.isFinite(length) && length > 0) || event.target.value.trim() === '') {
    showStatus('refused', `the true size must be a positive length, not "${event.target.value}"`);
    event.target.value = state.scene.true_size.length;
    return;
  }
  const next = structuredClone(latestScene());
  next.true_size.length = length;
  commit(next);
});
$('flip-depth').addEventListener('change', (event) => {
  if (state.mode !== 'photo' || !state.scene) return;
  const next = structuredClone(latestScene());
  next.symmetry.flip_depth = event.target.checked;
  commit(next);
});
$('back-side').addEventListener('change', (event) => {
  if (state.mode !== 'photo' || !state.scene) return;
  const next = structuredClone(latestScene());
  if (event.target.value === 'visible') delete next.back_side;
  else next.back_side = event.target.value;
  commit(next);
});
$('photo-pane').addEventListener('change', (event) => {
  $('photo-editor').hidden = event.target.value !== 'photo';
  render();
});

// ---------------------------------------------------------------- pattern view

/** CSS pixels per millimetre (the pattern's user unit) at true scale. */
const CSS_PX_PER_MM = 96 / 25.4;

function drawPattern(svg) {
  $('pattern').innerHTML = svg;
  state.highlight = null;
  // A new drawing (and model): the bend piece lit, if any, is lit again on it.
  const lit = state.litPiece ?? null;
  state.litPiece = null;
  queueMicrotask(() => {
    const pieces = state.reply && state.reply.model && state.reply.model.face_pieces;
    if (state.mode === 'bend' && lit !== null && state.litPiece === null && pieces && Array.prototype.includes.call(pieces, lit)) highlightBendPiece(lit);
  });
  // A pattern larger than the pane is fitted to it, unless the user chose the scale.
  const drawn = $('pattern').querySelector('svg');
  if (drawn && !state.fitChosen) {
    const box = drawn.viewBox.baseVal;
    const pane = $('pattern-view');
    const fits = box && box.width * CSS_PX_PER_MM <= pane.clientWidth - 24 && box.height * CSS_PX_PER_MM <= pane.clientHeight - 40;
    $('fit').checked = !fits;
    $('pattern').classList.toggle('fit', !fits);
  }
  readableLabels();
  drawSheetHandles();
}

// ---------------------------------------------------------------- the flat sheet's handles (bend)

const SVG_NS = 'http://www.w3.org/2000/svg';
const MM_PER_UNIT = { mm: 1, cm: 10, m: 1000, in: 25.4 };

/** The pattern drawing's matrix from the scene's flat coordinates (model units) to the
 * SVG's user units: the cut loop's `data-flat-transform` (first layout in mm → drawing)
 * after the unit's scale. Null without a pattern. */
function flatMatrix() {
  const path = $('pattern').querySelector('svg #cut path[data-flat-transform]');
  if (!path || !state.scene) return null;
  const [a, b, c, d, e, f] = path.dataset.flatTransform.replace(/[^-\d.e ]/g, ' ').trim().split(/\s+/).map(Number);
  const k = MM_PER_UNIT[state.scene.units || 'mm'] || 1;
  return new DOMMatrix([a * k, b * k, c * k, d * k, e, f]);
}

/** A flat point `[x, y]` of the scene in the drawing's user units. */
function flatToDrawing(matrix, p) {
  const q = new DOMPoint(p[0], p[1]).matrixTransform(matrix);
  return [q.x, q.y];
}

/** The page → flat sheet (model units) mapping of the pattern as drawn now, or null. */
function screenToSheet() {
  const svg = $('pattern').querySelector('svg');
  const matrix = flatMatrix();
  if (!svg || !matrix) return null;
  return matrix.inverse().multiply(svg.getScreenCTM().inverse());
}

/** Where the pointer is on the scene's flat sheet (model units), by `mapping` (default:
 * the pattern as drawn now). A drag keeps the mapping it began with: the pattern is
 * redrawn round its new bounds at each step, and a corner dragged outward would
 * otherwise move the drawing under the pointer and run away from it. */
function pointerOnSheet(event, mapping = screenToSheet()) {
  if (!mapping) return null;
  const q = new DOMPoint(event.clientX, event.clientY).matrixTransform(mapping);
  return [q.x, q.y];
}

/** The flat segment of region `k`: its start and its end (the curve's length along its
 * direction), or null when a flat curve sets where it lies. */
function flatSegment(scene, k) {
  const region = scene.regions[k];
  if (!region.flat_start) return null;
  const start = region.flat_start;
  const d = region.flat_direction || (region.flat_end ? [region.flat_end[0] - start[0], region.flat_end[1] - start[1]] : [1, 0]);
  const norm = Math.hypot(d[0], d[1]) || 1;
  const lengthMm = state.reply && state.reply.report.regions && state.reply.report.regions[k] && state.reply.report.regions[k].curve_length_mm;
  const length = (lengthMm || 0) / (MM_PER_UNIT[scene.units || 'mm'] || 1);
  const u = [d[0] / norm, d[1] / norm];
  const arc = region.flat_curve && region.flat_curve.type === 'arc' ? region.flat_curve : null;
  if (!arc) return { start, end: [start[0] + u[0] * length, start[1] + u[1] * length], path: null };
  // A flat arc (§5) leaves the start along the direction: drawn as the arc, its
  // direction handle a third of the way along its tangent.
  const side = arc.turn === 'right' ? -1 : 1;
  const centre = [start[0] - side * u[1] * arc.radius, start[1] + side * u[0] * arc.radius];
  const from = Math.atan2(start[1] - centre[1], start[0] - centre[0]);
  const path = Array.from({ length: 65 }, (_, i) => {
    const angle = from + (side * (i / 64) * length) / arc.radius;
    return [centre[0] + arc.radius * Math.cos(angle), centre[1] + arc.radius * Math.sin(angle)];
  });
  return { start, end: [start[0] + (u[0] * length) / 3, start[1] + (u[1] * length) / 3], path };
}

/** Handles on the flat sheet, drawn over the pattern (bend mode): each vertex of the
 * outline and of the holes (drag it; Shift+click deletes it; double-click an edge to
 * insert one), and each region's flat segment (blue: drag its start, or its end to turn
 * it). Every change is an edit of the library's that stops at the boundary of the
 * admissible shapes. */
function drawSheetHandles() {
  const svg = $('pattern').querySelector('svg');
  const matrix = flatMatrix();
  if (state.mode !== 'bend' || !svg || !matrix) return;
  const scene = state.scene;
  const group = document.createElementNS(SVG_NS, 'g');
  group.id = 'sheet-handles';
  const element = (name, attributes) => {
    const e = document.createElementNS(SVG_NS, name);
    for (const [k, v] of Object.entries(attributes)) e.setAttribute(k, v);
    group.appendChild(e);
    return e;
  };
  const loops = [[undefined, scene.outline], ...(scene.holes || []).map((h, k) => [k, h])];
  for (const [hole, vertices] of loops) {
    vertices.forEach((p, i) => {
      const [x1, y1] = flatToDrawing(matrix, p);
      const [x2, y2] = flatToDrawing(matrix, vertices[(i + 1) % vertices.length]);
      const edge = element('line', { x1, y1, x2, y2, class: 'sheet-edge', 'data-after': i });
      if (hole !== undefined) edge.dataset.hole = hole;
    });
    vertices.forEach((p, i) => {
      const [cx, cy] = flatToDrawing(matrix, p);
      const vertex = element('circle', { cx, cy, r: 1, class: 'sheet-vertex', 'data-index': i });
      if (hole !== undefined) vertex.dataset.hole = hole;
    });
  }
  scene.regions.forEach((_, k) => {
    const segment = flatSegment(scene, k);
    if (!segment) return;
    const [x1, y1] = flatToDrawing(matrix, segment.start);
    const [x2, y2] = flatToDrawing(matrix, segment.end);
    element('line', { x1, y1, x2, y2, class: 'flat-segment' });
    if (segment.path) element('polyline', { points: segment.path.map((p) => flatToDrawing(matrix, p).join(',')).join(' '), class: 'flat-segment' });
    element('circle', { cx: x1, cy: y1, r: 1, class: 'flat-handle', 'data-region': k, 'data-what': 'start' });
    element('circle', { cx: x2, cy: y2, r: 1, class: 'flat-handle', 'data-region': k, 'data-what': 'direction' });
  });
  svg.appendChild(group);
  sizeSheetHandles();
}

/** Handles 6 screen pixels in radius at any zoom. */
function sizeSheetHandles() {
  const r = 6 / patternScale();
  for (const circle of $('pattern').querySelectorAll('#sheet-handles circle')) circle.setAttribute('r', r.toFixed(4));
}

let sheetDrag = null; // { edit fields, before, moved }

/** Once the requests under way are answered: the scene `before` (JSON; null: none) goes
 * on the undo stack when the design changed from it — the same design, not one loaded
 * meanwhile (its history is its own) — then `then` runs. One step of the history for a
 * drag or a one-off edit, however many requests it made. */
function rememberWhenSettled(before, then = () => {}) {
  const generation = state.generation;
  const settle = () => {
    if (before !== null && state.generation === generation && JSON.stringify(state.scene) !== before) {
      state.undo.push(before);
      state.redo = [];
      updateHistoryButtons();
    }
    then();
  };
  if (state.inFlight) window.addEventListener('sheetform-idle', settle, { once: true });
  else settle();
}

/** An edit of the flat sheet (or of a parameter) that is not a drag: applied (or
 * refused) as one step of the history. */
function editOnce(edit) {
  const before = JSON.stringify(state.scene);
  requestSolve(state.scene, performance.now(), edit);
  rememberWhenSettled(before);
}

$('pattern').addEventListener('pointerdown', (event) => {
  const target = event.target;
  if (state.mode === 'bend') highlightBendPiece(null);
  if (addingBend || state.mode !== 'bend' || event.button !== 0 || !target.closest || !target.closest('#sheet-handles')) return;
  const hole = target.dataset.hole === undefined ? null : Number(target.dataset.hole);
  if (target.classList.contains('sheet-vertex')) {
    event.preventDefault();
    if (event.shiftKey) {
      editOnce({ kind: 'delete_outline_vertex', hole, index: Number(target.dataset.index) });
      return;
    }
    sheetDrag = { kind: 'move_outline_vertex', hole, index: Number(target.dataset.index), handle: target };
  } else if (target.classList.contains('flat-handle')) {
    event.preventDefault();
    if (event.shiftKey && target.dataset.what === 'start') {
      const scene = structuredClone(latestScene());
      if (scene.regions.length < 2) {
        showStatus('refused', 'a bend sheet keeps at least one curved region');
        return;
      }
      scene.regions.splice(Number(target.dataset.region), 1);
      commit(scene);
      return;
    }
    sheetDrag = { kind: 'move_flat_segment', region: Number(target.dataset.region), what: target.dataset.what, handle: target };
  } else {
    return;
  }
  sheetDrag.before = JSON.stringify(state.scene);
  sheetDrag.moved = false;
  sheetDrag.mapping = screenToSheet();
  $('pattern').setPointerCapture(event.pointerId);
});

$('pattern').addEventListener('pointermove', (event) => {
  if (!sheetDrag) return;
  const started = performance.now();
  const p = pointerOnSheet(event, sheetDrag.mapping);
  if (!p) return;
  sheetDrag.moved = true;
  if (sheetDrag.kind === 'move_outline_vertex') {
    requestSolve(state.scene, started, { kind: 'move_outline_vertex', hole: sheetDrag.hole, index: sheetDrag.index, position: p });
  } else if (sheetDrag.what === 'start') {
    requestSolve(state.scene, started, { kind: 'move_flat_segment', region: sheetDrag.region, start: p });
  } else {
    const { start } = flatSegment(state.scene, sheetDrag.region);
    requestSolve(state.scene, started, { kind: 'move_flat_segment', region: sheetDrag.region, direction: [p[0] - start[0], p[1] - start[1]] });
  }
});

function endSheetDrag(event) {
  if (!sheetDrag) return;
  const { before, moved } = sheetDrag;
  sheetDrag = null;
  if ($('pattern').hasPointerCapture(event.pointerId)) $('pattern').releasePointerCapture(event.pointerId);
  rememberWhenSettled(moved ? before : null);
}
$('pattern').addEventListener('pointerup', endSheetDrag);
$('pattern').addEventListener('pointercancel', endSheetDrag);

$('pattern').addEventListener('dblclick', (event) => {
  const target = event.target;
  if (state.mode !== 'bend' || !target.classList || !target.classList.contains('sheet-edge')) return;
  const hole = target.dataset.hole === undefined ? null : Number(target.dataset.hole);
  const after = Number(target.dataset.after);
  const vertices = hole === null ? state.scene.outline : state.scene.holes[hole];
  const a = vertices[after];
  const b = vertices[(after + 1) % vertices.length];
  const p = pointerOnSheet(event);
  if (!p) return;
  // The new vertex on the edge, where it was clicked: the shape does not change.
  const ab = [b[0] - a[0], b[1] - a[1]];
  const t = Math.min(1, Math.max(0, ((p[0] - a[0]) * ab[0] + (p[1] - a[1]) * ab[1]) / (ab[0] ** 2 + ab[1] ** 2 || 1)));
  editOnce({ kind: 'insert_outline_vertex', hole, after, position: [a[0] + t * ab[0], a[1] + t * ab[1]] });
});

// ---------------------------------------------------------------- new designs

/** The length of a Bézier curve (control points `[x, y, z]`), by 512 chords. */
function bezierLength(points) {
  const at = (t) => {
    let p = points.map((q) => [...q]);
    while (p.length > 1) p = p.slice(1).map((q, i) => q.map((x, a) => (1 - t) * p[i][a] + t * x));
    return p[0];
  };
  let length = 0;
  let last = at(0);
  for (let i = 1; i <= 512; i++) {
    const next = at(i / 512);
    length += Math.hypot(next[0] - last[0], next[1] - last[1], next[2] - last[2]);
    last = next;
  }
  return length;
}

/** A planar curl `length` long (the curve's own frame: it leaves the origin along +x and
 * rises in the xz plane), to reshape: the curve of a new bend. */
function planarCurl(length) {
  const shape = [[0, 0, 0], [70, 0, 0], [130, 0, 20], [170, 0, 80]];
  const k = length / bezierLength(shape);
  return shape.map((p) => p.map((x) => Math.round(x * k * 1e6) / 1e6));
}

/** The slit templates (the bundled examples' designs, Tsuruta et al.). */
const SLIT_TEMPLATES = {
  chair: {
    name: 'chair', units: 'mm',
    sheet: { l1_width: 420, l2_panel_length: 430, l3_strip_length: 300, l4_slit_width: 6, strip_count: 6, quads_per_strip: 10 },
    leg_curve: { control_points: [[350, 0], [315, 240], [240, 445]] },
    seat_curve: { control_points: [[0, 360], [140, 300], [300, 330], [420, 470]] },
  },
  bench: {
    name: 'bench', units: 'mm',
    sheet: { l1_width: 360, l2_panel_length: 380, l3_strip_length: 420, l4_slit_width: 5, strip_count: 4, quads_per_strip: 10 },
    leg_curve: { control_points: [[410, 0], [395, 200], [360, 395]] },
    seat_curve: { control_points: [[0, 330], [180, 322], [360, 330]] },
  },
};

/** A new bend sheet: a 240 × 120 mm rectangle bent by one planar curl along its middle,
 * every part of it to reshape (the sheet's corners, the flat segment, the curve). */
function newBendScene() {
  return {
    name: 'new sheet',
    units: 'mm',
    outline: [[0, -60], [240, -60], [240, 60], [0, 60]],
    regions: [{ name: 'bend 1', flat_start: [20, 0], flat_direction: [1, 0], curve: { type: 'bezier', control_points: planarCurl(180) } }],
  };
}

/** A new FFD design around the mesh `path` (relative to the served directory): a cubic
 * 4 × 4 × 4 lattice round its bounding box, and a first deformation with no edit yet
 * (drag a lattice point to add one). */
function newFfdScene(path, upAxis) {
  return {
    name: path.split('/').at(-1).replace(/\.[^.]*$/, ''),
    units: 'mm',
    up_axis: upAxis,
    model: { mesh: path },
    lattice: { degrees: [3, 3, 3], counts: [4, 4, 4], margin: 0.05 },
    deformations: [{ name: 'start', edits: [] }],
  };
}

$('new-ffd').addEventListener('click', () => openChooser('mesh-chooser', 'mesh-choice', 'mesh-chosen', 'meshes'));
$('mesh-chooser').addEventListener('close', () => {
  if ($('mesh-chooser').returnValue !== 'chosen' || !$('mesh-choice').value) return;
  load(JSON.stringify(newFfdScene($('mesh-choice').value, $('mesh-up').value), null, 2), null);
});

/** The lattice's counts in their fields (FFD mode). */
function fillLatticeFields(scene) {
  const counts = (scene && scene.lattice && scene.lattice.counts) || [4, 4, 4];
  ['lattice-u', 'lattice-v', 'lattice-w'].forEach((id, a) => { $(id).value = counts[a]; });
}
for (const id of ['lattice-u', 'lattice-v', 'lattice-w']) {
  $(id).addEventListener('change', () => {
    if (state.mode !== 'ffd' || !state.scene) return;
    const counts = ['lattice-u', 'lattice-v', 'lattice-w'].map((k) => Number($(k).value));
    if (!counts.every((n) => Number.isInteger(n) && n >= 2)) {
      fillLatticeFields(state.scene);
      showStatus('refused', 'a lattice count is a whole number of at least 2');
      return;
    }
    const scene = structuredClone(latestScene());
    scene.lattice = { ...scene.lattice, counts };
    commit(scene);
  });
}

$('new-design').addEventListener('click', () => {
  const scene = state.mode === 'slit' ? structuredClone(SLIT_TEMPLATES[$('slit-template').value]) : newBendScene();
  // An unsaved design: Save asks where it goes.
  load(JSON.stringify(scene, null, 2), null);
});

/** Adding a bend: the first click on the pattern is its flat segment's start. */
let addingBend = null;

$('add-bend').addEventListener('click', () => {
  if (state.mode !== 'bend' || !state.scene) return;
  addingBend = { start: null };
  $('pattern').classList.add('adding');
  showStatus('busy', 'a new bend: click on the pattern where its flat segment starts, then where it ends');
});

$('pattern').addEventListener('click', (event) => {
  if (!addingBend || state.mode !== 'bend') return;
  const p = pointerOnSheet(event);
  if (!p) return;
  if (!addingBend.start) {
    addingBend.start = p;
    showStatus('busy', 'a new bend: now click where its flat segment ends');
    return;
  }
  const a = addingBend.start;
  addingBend = null;
  $('pattern').classList.remove('adding');
  const d = [p[0] - a[0], p[1] - a[1]];
  const length = Math.hypot(d[0], d[1]);
  if (!(length > 0)) {
    showStatus('refused', 'a flat segment needs two different points');
    return;
  }
  const scene = structuredClone(latestScene());
  const n = scene.regions.length + 1;
  scene.regions.push({ name: `bend ${n}`, flat_start: a, flat_direction: d, curve: { type: 'bezier', control_points: planarCurl(length) } });
  commit(scene);
});

/** Screen pixels per pattern millimetre as drawn now (the drawing keeps its aspect in
 * the svg's box: the smaller of the two ratios). */
function patternScale() {
  const svg = $('pattern').querySelector('svg');
  const box = svg && svg.viewBox.baseVal;
  if (!box || !(box.width > 0) || !(box.height > 0)) return CSS_PX_PER_MM;
  const drawn = svg.getBoundingClientRect();
  return Math.min(drawn.width / box.width, drawn.height / box.height);
}

/** Labels at least 10 screen pixels high at any zoom (the files keep their sizes; the
 * strokes are scale-independent by the style sheet). */
function readableLabels() {
  const scale = patternScale();
  if (!(scale > 0)) return;
  $('pattern-scale').textContent = $('fit').checked
    ? `Flat pattern fitted to the view (1 mm = ${(scale / CSS_PX_PER_MM).toPrecision(2)} CSS mm)`
    : 'Flat pattern at true scale (1 mm = 1 CSS mm)';
  // Dashes are drawn in screen pixels with non-scaling strokes: each layer's pattern (in
  // mm) at its true-scale size on screen, or larger when zoomed in.
  const dash = Math.max(scale, CSS_PX_PER_MM);
  for (const layer of $('pattern').querySelectorAll('svg g[stroke-dasharray]')) {
    if (!layer.dataset.dash) layer.dataset.dash = layer.getAttribute('stroke-dasharray');
    if (layer.dataset.dash === 'none') continue;
    layer.style.strokeDasharray = layer.dataset.dash.split(/[ ,]+/).map((v) => `${(Number(v) * dash).toFixed(2)}px`).join(' ');
  }
  for (const text of $('pattern').querySelectorAll('#labels text')) {
    if (!text.dataset.size) text.dataset.size = text.getAttribute('font-size');
    const size = Number(text.dataset.size);
    if (size > 0) text.setAttribute('font-size', Math.max(size, 10 / scale).toFixed(3));
  }
}

// ---------------------------------------------------------------- pieces and IDs, 2D ↔ 3D

/** The mesh pieces of pattern piece `piece` (its cut loops' `data-mesh-pieces`). */
function meshPiecesOf(svg, piece) {
  const path = svg.querySelector(`path[data-piece="${piece}"]`);
  return path ? path.dataset.meshPieces.split(' ').filter(Boolean).map(Number) : [];
}

/** Lights up the mesh pieces `pieces` (face_pieces values; null: none) on the 3D model and
 * the pattern pieces holding them in 2D (their cut loops and names), and the seam ID
 * `seam` on both its copies. */
function highlightPieces(pieces, seam = null) {
  const key = pieces ? `${[...pieces].sort().join(' ')}|${seam}` : null;
  if ((state.highlight && state.highlight.key) === key || (!state.highlight && key === null)) return;
  state.highlight = pieces ? { key, pieces: [...pieces].sort((a, b) => a - b), seam } : null;
  const svg = $('pattern').querySelector('svg');
  if (svg) {
    for (const element of svg.querySelectorAll('.lit')) element.classList.remove('lit');
    if (pieces) {
      const lit = new Set();
      for (const path of svg.querySelectorAll('path[data-mesh-pieces]')) {
        if (path.dataset.meshPieces.split(' ').some((p) => p !== '' && pieces.has(Number(p)))) {
          path.classList.add('lit');
          lit.add(path.dataset.piece);
        }
      }
      for (const text of svg.querySelectorAll('text.piece[data-piece]')) if (lit.has(text.dataset.piece)) text.classList.add('lit');
      if (seam !== null) for (const text of svg.querySelectorAll(`text[data-seam="${CSS.escape(seam)}"]`)) text.classList.add('lit');
    }
  }
  if (state.mode === 'mesh' && state.reply && $('colour').value === 'pieces') {
    // The model's pieces: those lit keep their colour, the others fade to paper.
    const colour = sheet.geometry.getAttribute('color');
    const paper = new THREE.Color(0xeeece6);
    const faces = state.reply.model.face_pieces;
    for (let t = 0; t < faces.length && 3 * t + 2 < colour.count; t++) {
      const c = pieceColour(faces[t]);
      if (pieces && !pieces.has(faces[t])) c.lerp(paper, 0.8);
      for (let k = 0; k < 3; k++) colour.setXYZ(3 * t + k, c.r, c.g, c.b);
    }
    colour.needsUpdate = true;
    render();
  }
}

// Pointing at a piece or a seam ID on the pattern lights it up on the model; at a seam
// ID, both copies and both pieces.
$('pattern').addEventListener('pointerover', (event) => {
  if (state.mode !== 'mesh') return;
  const svg = $('pattern').querySelector('svg');
  const element = event.target.closest && event.target.closest('[data-piece]');
  if (!svg || !element) return;
  if (element.dataset.seam !== undefined) {
    const pieces = new Set();
    for (const copy of svg.querySelectorAll(`text[data-seam="${CSS.escape(element.dataset.seam)}"]`)) {
      for (const p of meshPiecesOf(svg, copy.dataset.piece)) pieces.add(p);
    }
    highlightPieces(pieces, element.dataset.seam);
  } else {
    highlightPieces(new Set(meshPiecesOf(svg, element.dataset.piece)));
  }
});
$('pattern').addEventListener('pointerleave', () => highlightPieces(null));

/** Bend mode: the face of the reply's model whose flat triangle holds flat point `p`
 * (model units), or -1. */
function flatFaceAt(p) {
  const { flat: uv, triangles: f } = state.reply.model;
  for (let t = 0; 3 * t + 2 < f.length; t++) {
    const [a, b, c] = [f[3 * t], f[3 * t + 1], f[3 * t + 2]];
    const [ax, ay, bx, by, cx, cy] = [uv[2 * a], uv[2 * a + 1], uv[2 * b], uv[2 * b + 1], uv[2 * c], uv[2 * c + 1]];
    const area = (bx - ax) * (cy - ay) - (by - ay) * (cx - ax);
    if (area === 0) continue;
    const u = ((bx - p[0]) * (cy - p[1]) - (by - p[1]) * (cx - p[0])) / area;
    const v = ((cx - p[0]) * (ay - p[1]) - (cy - p[1]) * (ax - p[0])) / area;
    if (u >= 0 && v >= 0 && u + v <= 1) return t;
  }
  return -1;
}

/** Bend mode: lights piece `piece` of the reply's model (its `face_pieces` label, a
 * curved region or a planar part; null: none) over the sheet in 3D and on the pattern
 * (a path over the piece's flat triangles, `#lit-piece`), its name in the pattern's
 * caption. */
function highlightBendPiece(piece) {
  if ((state.litPiece ?? null) === piece) return;
  state.litPiece = piece;
  const svg = $('pattern').querySelector('svg');
  const old = svg && svg.querySelector('#lit-piece');
  if (old) old.remove();
  litPiece.geometry.dispose();
  litPiece.geometry = new THREE.BufferGeometry();
  const matrix = flatMatrix();
  let faceCount = 0;
  if (piece !== null && state.reply && state.reply.model) {
    const { positions: p, flat: uv, triangles: f, face_pieces: pieces } = state.reply.model;
    const corners = [];
    let d = '';
    for (let t = 0; t < pieces.length; t++) {
      if (pieces[t] !== piece) continue;
      faceCount += 1;
      const vertices = [f[3 * t], f[3 * t + 1], f[3 * t + 2]];
      for (const v of vertices) corners.push(p[3 * v], p[3 * v + 1], p[3 * v + 2]);
      if (svg && matrix) {
        const [a, b, c] = vertices.map((v) => flatToDrawing(matrix, [uv[2 * v], uv[2 * v + 1]]).map((x) => x.toFixed(3)));
        d += `M${a}L${b}L${c}Z`;
      }
    }
    litPiece.geometry.setAttribute('position', new THREE.Float32BufferAttribute(corners, 3));
    if (svg && d) {
      const path = document.createElementNS(SVG_NS, 'path');
      path.id = 'lit-piece';
      path.dataset.meshPiece = piece;
      path.setAttribute('d', d);
      // Under the handles: the sheet's vertices and flat segments stay draggable.
      svg.insertBefore(path, svg.querySelector('#sheet-handles'));
    }
  }
  // A piece with no face in this model is not lit.
  if (faceCount === 0) state.litPiece = null;
  // Curved pieces are the regions, in order; the planar parts follow (named as the
  // pattern labels them).
  const regions = (state.reply && state.reply.report && state.reply.report.regions) || [];
  $('pattern').title = faceCount === 0 ? '' : piece < regions.length ? regions[piece].name : `planar-${piece - regions.length}`;
  render();
}

// Bend mode: the piece under the pointer on the pattern lights up on the model.
$('pattern').addEventListener('pointermove', (event) => {
  if (state.mode !== 'bend' || sheetDrag || event.buttons !== 0 || !state.reply || !state.reply.model) return;
  const p = pointerOnSheet(event);
  const t = p ? flatFaceAt(p) : -1;
  highlightBendPiece(t >= 0 ? state.reply.model.face_pieces[t] : null);
});
$('pattern').addEventListener('pointerleave', () => { if (state.mode === 'bend') highlightBendPiece(null); });
$('fit').addEventListener('change', (e) => {
  state.fitChosen = true;
  $('pattern').classList.toggle('fit', e.target.checked);
  readableLabels();
  sizeSheetHandles();
});
window.addEventListener('resize', () => { readableLabels(); sizeSheetHandles(); });

// ---------------------------------------------------------------- status

const short = (x, digits = 3) => (x === null || x === undefined ? '–' : Number(x).toPrecision(digits));

function showStatus(kind, text) {
  const footer = $('status');
  footer.dataset.state = kind;
  footer.textContent = text;
}

function showSlitReport(reply, roundTrip) {
  const r = reply.report;
  const strips = r.slit.strips;
  const gap = Math.max(...strips.map((s) => s.gap_mm));
  const parts = [
    `${r.status}`,
    `${strips.length} strips (${r.slit.solve_mode})`,
    `largest gap ${short(gap, 2)} mm`,
    `isometry error ${short(r.isometry_error_max_relative, 2)}`,
    `server ${short(reply.server_ms)} ms`,
    roundTrip === undefined ? null : `round trip ${short(roundTrip)} ms`,
  ];
  showStatus(r.status === 'ok' ? 'ok' : 'refused', parts.filter(Boolean).join(' · '));
  // The gap each strip leaves at the seat curve, live (Tsuruta et al. Eq. 1's no-gap term).
  $('strip-gaps').innerHTML = '<strong>gap per strip</strong>' + strips
    .map((s) => `<div data-strip="${s.strip}">strip ${s.strip + 1}: ${short(s.gap_mm, 2)} mm${s.converged ? '' : ' (not converged)'}</div>`)
    .join('');
}

function showPhotoReport(reply) {
  const r = reply.report;
  const pieces = new Set(reply.model.face_pieces).size;
  const parts = [
    `${r.status}`,
    `${pieces} patch${pieces === 1 ? '' : 'es'}`,
    `${r.face_count} faces`,
    `isometry error ${short(r.isometry_error_max_relative, 2)}`,
    `server ${short(reply.server_ms)} ms`,
  ];
  showStatus(r.status === 'ok' ? 'ok' : 'refused', parts.filter(Boolean).join(' · '));
}

function showReport(reply, roundTrip) {
  if (state.mode === 'photo') {
    showPhotoReport(reply);
    return;
  }
  if (state.mode === 'slit') {
    showSlitReport(reply, roundTrip);
    return;
  }
  const r = reply.report;
  const margin = Math.min(...(r.regions || []).map((g) => g.regression_margin_mm ?? Infinity));
  const parts = [
    `${r.status}`,
    `${r.ruling_count ?? 0} rulings`,
    `${r.face_count} faces`,
    `isometry error ${short(r.isometry_error_max_relative, 2)}`,
    Number.isFinite(margin) ? `regression margin ${short(margin)} mm` : null,
    `server ${short(reply.server_ms)} ms`,
    roundTrip === undefined ? null : `round trip ${short(roundTrip)} ms`,
  ];
  if (reply.moved_fraction !== undefined && reply.moved_fraction < 1) {
    // The drag went past the admissible shapes: the point stopped at their boundary.
    showStatus('boundary', `stopped at the edge of what can bend (${Math.round(100 * reply.moved_fraction)} % of this move): ${reply.stopped_because} · ${parts.filter(Boolean).join(' · ')}`);
    return;
  }
  showStatus('ok', parts.filter(Boolean).join(' · '));
}

function showMeshReport(reply) {
  const r = reply.report;
  const d = reply.check_report.angle_defects || {};
  const pieces = new Set(reply.model.face_pieces).size;
  const developed = r.develop
    ? `developed: ${r.develop.piece_count} exact piece${r.develop.piece_count === 1 ? '' : 's'}, ` +
      `${short(100 * r.develop.hausdorff_relative, 2)} % from the target` +
      (r.develop.mirror_plane ? `, mirrored in ${r.develop.mirror_plane}` : '')
    : null;
  const parts = [
    state.mesh.name,
    `${r.status}`,
    developed || `${r.layout || ''} ${pieces} piece${pieces === 1 ? '' : 's'}`.trim(),
    `${reply.check_report.face_count} faces`,
    d.max_rad === undefined ? null : `largest angle defect ${short(d.max_rad, 2)} rad`,
    `isometry error ${short(r.isometry_error_max_relative, 2)}`,
    `server ${short(reply.server_ms)} ms`,
  ];
  showStatus(r.status === 'ok' ? 'ok' : 'refused', parts.filter(Boolean).join(' · '));
}

// ---------------------------------------------------------------- solving

/** The directory of the scene file in the served directory ('' for one from disk). */
function sceneDirectory() {
  return state.path ? state.path.split('/').slice(0, -1).join('/') : '';
}

/** `?dir=…`: the server reads the scene's assets relative to its directory, as the CLI. */
function dirQuery() {
  return `?dir=${encodeURIComponent(sceneDirectory())}`;
}

/** The media type of a reply whose large arrays come in binary (the server's array_reply.rs). */
const ARRAYS_MEDIA_TYPE = 'application/vnd.sheetform.arrays';
/** Typed arrays view the reply's bytes as they are, which needs a little-endian machine
 * (every browser's); elsewhere the page asks for JSON. */
const LITTLE_ENDIAN = new Uint8Array(new Uint16Array([1]).buffer)[0] === 1;
/** What the page accepts in reply to a solve: binary arrays first. */
const SOLVE_ACCEPT = LITTLE_ENDIAN ? `${ARRAYS_MEDIA_TYPE}, application/json` : 'application/json';


function holdArray(path, hash, value) {
  let byHash = heldArrays.get(path);
  if (!byHash) {
    byHash = new Map();
    heldArrays.set(path, byHash);
  }
  byHash.delete(hash);
  byHash.set(hash, value);
  while (byHash.size > HELD_PER_PATH) byHash.delete(byHash.keys().next().value);
}

/** A reply left out an array the page no longer holds (evicted, or cleared by a load). */
class HeldArrayMissing extends Error {}

/** The headers of a solve request: binary arrays accepted, and (`held`) the arrays held. */
function solveHeaders(contentType, held = true) {
  const headers = { Accept: SOLVE_ACCEPT };
  if (contentType) headers['Content-Type'] = contentType;
  if (held && LITTLE_ENDIAN && heldArrays.size) {
    headers['X-Sheetform-Held-Arrays'] = [...heldArrays].map(([path, byHash]) => `${path}=${[...byHash.keys()].pop()}`).join(',');
  }
  return headers;
}

async function post(url, body) {
  const response = await fetch(url, { method: 'POST', headers: solveHeaders('application/json', false), body });
  return response;
}

/**
 * A solve request and its reply read (`readReply`), naming the arrays the page holds; a
 * reply that left out one the page no longer holds is asked for again without them.
 */
async function fetchReply(url, body, contentType) {
  const generation = state.generation;
  for (const held of [true, false]) {
    const response = await fetch(url, { method: 'POST', headers: solveHeaders(contentType, held), body });
    // When the headers came (the body's download and decoding follow).
    const received = performance.now();
    try {
      return { response, received, body: await readReply(response) };
    } catch (error) {
      // Asked again only for the scene still shown (a reply to an older one is dropped).
      if (!held || !(error instanceof HeldArrayMissing) || state.generation !== generation) throw error;
    }
  }
  throw new Error('unreachable');
}

/**
 * A solve's reply: JSON, or a JSON header and binary arrays (`SFA1`, the header's length,
 * the header, then each array at its offset, 8-aligned, from the 8-aligned end of the
 * header), each put back at its path as a typed array over the reply's bytes (no number
 * is formatted or parsed). Rulings come as offsets then indices: they become subarrays.
 */
async function readReply(response) {
  if (response.headers.get('Content-Type') !== ARRAYS_MEDIA_TYPE) return response.json();
  const buffer = await response.arrayBuffer();
  const view = new DataView(buffer);
  if (buffer.byteLength < 8 || view.getUint32(0, false) !== 0x53464131) throw new Error('a binary reply without its SFA1 mark');
  const headerLength = view.getUint32(4, true);
  const body = JSON.parse(new TextDecoder().decode(new Uint8Array(buffer, 8, headerLength)));
  const start = Math.ceil((8 + headerLength) / 8) * 8;
  state.arraysReceived = state.arraysReceived || { sent: 0, held: 0 };
  for (const { path, type, offset, length, hash, held } of body.binary_arrays) {
    const at = start + offset;
    let value;
    if (held) {
      value = heldArrays.get(path) && heldArrays.get(path).get(hash);
      if (!value || value.length !== length) throw new HeldArrayMissing(`the reply left out ${path}, which the page no longer holds`);
      state.arraysReceived.held += 1;
      holdArray(path, hash, value);
    } else if (type === 'f64') {
      value = new Float64Array(buffer, at, length);
    } else if (type === 'u32') {
      value = new Uint32Array(buffer, at, length);
    } else {
      const offsets = new Uint32Array(buffer, at, length + 1);
      const values = new Uint32Array(buffer, at + 4 * (length + 1), offsets[length]);
      value = Array.from({ length }, (_, k) => values.subarray(offsets[k], offsets[k + 1]));
    }
    if (!held) {
      state.arraysReceived.sent += 1;
      if (hash) holdArray(path, hash, value);
    }
    const keys = path.split('.');
    const owner = keys.slice(0, -1).reduce((object, key) => object[key], body);
    owner[keys[keys.length - 1]] = value;
  }
  delete body.binary_arrays;
  return body;
}

/**
 * Sends a scene (or, with `edit`, an edit of the last admissible scene: the library's
 * editor applies it) to the server; the newest request wins while one is in flight.
 */
/** The newest scene asked for: the one waiting or being solved, else the current one.
 * A click's edit builds on it, so an edit made while the last one is still being
 * solved adds to it instead of replacing it. (A drag's moves build on `state.scene`,
 * the last admissible scene, each move whole.) */
function latestScene() {
  return state.requested || state.scene;
}

function requestSolve(scene, started = performance.now(), edit = null) {
  state.requested = edit ? null : scene;
  if (state.inFlight) {
    state.pending = { scene, started, edit };
    return;
  }
  state.inFlight = true;
  solveNow(scene, started, edit).finally(() => {
    state.inFlight = false;
    const next = state.pending;
    state.pending = null;
    if (next) {
      requestSolve(next.edit ? state.scene : next.scene, next.started, next.edit);
    } else {
      state.requested = null;
      window.dispatchEvent(new Event('sheetform-idle'));
    }
  });
}

async function solveNow(scene, started, edit) {
  const mode = state.mode;
  const generation = state.generation;
  let response;
  let body;
  const sent = performance.now();
  let received;
  let decoded;
  try {
    ({ response, body, received } = edit
      ? await fetchReply(`/api/bend/edit${dirQuery()}`, JSON.stringify({ scene, edit, stop_at_boundary: true }), 'application/json')
      : await fetchReply(`/api/${mode}${dirQuery()}`, JSON.stringify(scene), 'application/json'));
    decoded = performance.now();
    state.answers += 1;
    // The user switched modes or loaded another scene meanwhile: not drawn.
    if (state.mode !== mode || state.generation !== generation) return false;
  } catch (error) {
    state.lastError = String(error);
    showStatus('error', `the server did not answer: ${error}`);
    return false;
  }
  if (!response.ok && body.error && body.error.kind === 'at_boundary') {
    // A drag held past the boundary of the admissible shapes: the point stays there.
    state.boundaryStops += 1;
    state.lastError = body.error;
    fillCurveParameters(state.scene);
    drawHandles(state.scene);
    render();
    showStatus('boundary', `stopped at the edge of what can bend: ${body.error.message}`);
    return false;
  }
  if (!response.ok) {
    state.refusals += 1;
    state.lastError = body.error;
    if (mode === 'photo' && photo.draft) {
      // A new annotation is traced curve by curve: each step is kept until the first
      // reconstruction (and undoable), the reason it does not reconstruct yet shown.
      state.scene = scene;
      state.sceneByMode.photo = scene;
      drawPhotoEditor(scene);
      showStatus('refused', `not reconstructed (${body.error.kind.replace('_', ' ')}): ${body.error.message}`);
      return false;
    }
    drawHandles(state.scene || scene);
    if (state.mode === 'slit' && state.scene) fillSlitInputs(state.scene);
    if (state.mode === 'bend') fillCurveParameters(state.scene);
    render();
    const kept = state.scene ? ' — kept the last admissible shape' : '';
    showStatus('refused', `refused (${body.error.kind.replace('_', ' ')}): ${body.error.message}${kept}`);
    return false;
  }
  if (edit) {
    scene = body.scene;
    state.lastEdit = { ...body.edit, moved_fraction: body.moved_fraction, stopped_because: body.stopped_because };
    if (body.moved_fraction < 1) state.boundaryStops += 1;
  }
  state.scene = scene;
  state.sceneByMode[state.mode] = scene;
  state.reply = body;
  state.lastError = null;
  if (state.mode === 'slit') fillSlitInputs(scene);
  if (state.mode === 'bend') fillCurveParameters(scene);
  drawModel(body.model, body.angle_defects_rad);
  drawRegression(body.regression_curves || []);
  drawHandles(scene);
  drawPattern(body.pattern_svg);
  const scripted = performance.now();
  render();
  // The round trip ends when the redraw has been issued (WebGL commands and the new
  // SVG); the browser shows it at its next frame, up to one display frame later.
  const drawn = performance.now();
  const roundTrip = drawn - started;
  state.roundTrips.push(roundTrip);
  await new Promise((resolve) => requestAnimationFrame(resolve));
  state.stages.push({
    queued: sent - started, server: body.server_ms, response: received - sent, parse_and_draw: drawn - received,
    // Of which: reading the reply's body, the page's own scripting (meshes, handles,
    // pattern), and the WebGL draw calls.
    decode: decoded - received, script: scripted - decoded, render: drawn - scripted,
    to_next_frame: performance.now() - drawn,
  });
  showReport(body, roundTrip);
  return true;
}

function showFfdReport(reply) {
  const r = reply.report;
  const f = r.ffd;
  const last = f.steps[f.steps.length - 1];
  const iterations = f.steps.reduce((n, s) => n + s.iterations, 0);
  const parts = [
    `${r.status}`,
    `${f.steps.length} deformation${f.steps.length === 1 ? '' : 's'}`,
    // The server resumes from its last design: only the new deformations are restored.
    reply.resumed_deformations ? `${reply.resumed_deformations} taken from the last result` : null,
    `last: max defect ${short(last.angle_defect_max_before_rad, 2)} → ${short(last.angle_defect_max_after_rad, 2)} rad`,
    `${iterations} iterations`,
    `edges changed ≤ ${short(100 * last.edge_length_change_max_relative, 2)} %`,
    `server ${short(reply.server_ms)} ms`,
  ];
  showStatus(r.status === 'ok' ? 'ok' : 'refused', parts.filter(Boolean).join(' · '));
}

/**
 * Runs an FFD scene on the server, showing its progress. `history` says what the run
 * does to the undo and redo stacks once the scene is restored, and only then:
 * `remember` puts the scene it replaces on the undo stack, `undo` and `redo` move the
 * scene across (the stacks are left alone when the run is refused or cancelled, so an
 * undo that did not happen leaves nothing to redo), `none` leaves them. A newer scene
 * cancels the run under way and waits for it to stop; a refused or cancelled run keeps
 * the last result.
 */
async function runFfd(scene, history = 'remember') {
  if (state.ffdController) {
    state.ffdPending = { scene, history };
    state.ffdController.abort();
    return;
  }
  const controller = new AbortController();
  const generation = state.generation;
  state.ffdController = controller;
  state.ffdRequested = scene;
  state.inFlight = true;
  state.progress = [];
  $('cancel').disabled = false;
  showStatus('busy', 'restoring…');
  const before = state.scene;
  try {
    const response = await fetch(`/api/ffd${dirQuery()}`, { method: 'POST', body: JSON.stringify(scene), signal: controller.signal });
    let last = null;
    if (!response.ok) {
      last = await response.json();
    } else {
      const reader = response.body.getReader();
      const decoder = new TextDecoder();
      let buffer = '';
      for (;;) {
        const { value, done } = await reader.read();
        if (done) break;
        buffer += decoder.decode(value, { stream: true });
        for (let end = buffer.indexOf('\n'); end >= 0; end = buffer.indexOf('\n')) {
          const message = JSON.parse(buffer.slice(0, end));
          buffer = buffer.slice(end + 1);
          if (message.progress) {
            state.progress.push(message.progress);
            showStatus('busy', `${message.progress.stage} (${Math.round(100 * message.progress.fraction)} %) — Cancel stops it`);
          } else {
            last = message;
          }
        }
      }
    }
    if (state.generation !== generation || state.mode !== 'ffd') return;
    if (!last || last.error) {
      state.refusals += 1;
      state.lastError = last ? last.error : { kind: 'failed', message: 'the server closed the stream' };
      drawHandles(state.scene);
      render();
      const kept = state.reply ? ' — kept the last result' : '';
      fillLatticeFields(state.scene);
      showStatus('refused', `refused (${state.lastError.kind.replace('_', ' ')}): ${state.lastError.message}${kept}`);
      return;
    }
    if (history === 'remember' && before) {
      state.undo.push(JSON.stringify(before));
      state.redo = [];
    } else if (history === 'undo' && before) {
      state.undo.pop();
      state.redo.push(JSON.stringify(before));
    } else if (history === 'redo' && before) {
      state.redo.pop();
      state.undo.push(JSON.stringify(before));
    }
    state.scene = scene;
    state.sceneByMode.ffd = scene;
    state.reply = last.result;
    state.lastError = null;
    fillLatticeFields(scene);
    drawFfdModel(last.result);
    drawPattern(last.result.pattern_svg);
    render();
    showFfdReport(last.result);
  } catch (error) {
    if (error.name === 'AbortError') {
      state.cancellations += 1;
      if (state.generation !== generation || state.mode !== 'ffd') return;
      drawHandles(state.scene);
      render();
      showStatus('refused', `cancelled${state.reply ? ' — kept the last result' : ''}`);
    } else {
      state.lastError = String(error);
      showStatus('error', `the server did not answer: ${error}`);
    }
  } finally {
    state.answers += 1;
    state.ffdController = null;
    state.ffdRequested = null;
    state.inFlight = false;
    $('cancel').disabled = true;
    updateHistoryButtons();
    const next = state.ffdPending;
    state.ffdPending = null;
    // A scene of another mode queued while this ran (after a mode switch) goes now.
    const queued = state.pending;
    state.pending = null;
    if (next && state.mode === 'ffd') runFfd(next.scene, next.history);
    else if (queued) requestSolve(queued.edit ? state.scene : queued.scene, queued.started, queued.edit);
    else window.dispatchEvent(new Event('sheetform-idle'));
  }
}

$('cancel').addEventListener('click', () => {
  state.ffdPending = null;
  if (state.ffdController) state.ffdController.abort();
});
$('bend-view').addEventListener('change', () => {
  if (state.mode !== 'bend' || !state.reply) return;
  drawModel(state.reply.model, state.reply.angle_defects_rad);
  render();
});
$('ffd-view').addEventListener('change', () => {
  if (state.mode === 'ffd' && state.reply) {
    drawFfdModel(state.reply);
    render();
  }
});

function updateHistoryButtons() {
  $('undo').disabled = state.undo.length === 0;
  $('redo').disabled = state.redo.length === 0;
}

/** Makes `scene` current through the server; `remember` puts the old one on the undo stack. */
function commit(scene, remember = true) {
  if (state.mode === 'ffd') {
    runFfd(scene, remember ? 'remember' : 'none');
    return;
  }
  if (remember && state.scene) {
    state.undo.push(JSON.stringify(latestScene()));
    state.redo = [];
  }
  updateHistoryButtons();
  requestSolve(scene);
}

function current() {
  return JSON.stringify(state.mode === 'mesh' ? state.meshOptions : state.scene);
}

function restore(text) {
  if (state.mode === 'mesh') solveMesh(JSON.parse(text));
  else requestSolve(JSON.parse(text));
}

function undo() {
  if (!state.undo.length) return;
  // FFD: the stacks move when the restoration of the earlier scene succeeds.
  if (state.mode === 'ffd') {
    runFfd(JSON.parse(state.undo[state.undo.length - 1]), 'undo');
    return;
  }
  state.redo.push(current());
  restore(state.undo.pop());
  updateHistoryButtons();
}

function redo() {
  if (!state.redo.length) return;
  if (state.mode === 'ffd') {
    runFfd(JSON.parse(state.redo[state.redo.length - 1]), 'redo');
    return;
  }
  state.undo.push(current());
  restore(state.redo.pop());
  updateHistoryButtons();
}

$('undo').addEventListener('click', undo);
$('drag-mode').addEventListener('change', () => { if (state.scene) { drawHandles(state.scene); render(); } });
$('redo').addEventListener('click', redo);
window.addEventListener('keydown', (e) => {
  if ((e.ctrlKey || e.metaKey) && e.key.toLowerCase() === 'z') {
    e.preventDefault();
    if (e.shiftKey) redo(); else undo();
    return;
  }
  // Drag locks, as in DCC tools: X, Y or Z locks the axis, with Shift the plane across
  // it; the same key again goes back to "auto". Not while typing in a field.
  const key = e.key.toLowerCase();
  if (e.repeat || e.ctrlKey || e.metaKey || e.altKey || !['x', 'y', 'z'].includes(key)) return;
  if (e.target instanceof HTMLInputElement || e.target instanceof HTMLTextAreaElement || e.target instanceof HTMLSelectElement) return;
  const lock = e.shiftKey ? { x: 'yz', y: 'zx', z: 'xy' }[key] : key;
  const select = $('drag-lock');
  select.value = select.value === lock ? 'auto' : lock;
  // During a drag the new lock goes through where the point is now.
  if (drag) drag.constraint = dragConstraint(drag, drag.point.clone());
});

// ---------------------------------------------------------------- dragging

const raycaster = new THREE.Raycaster();
let drag = null; // { region, index, plane, before, moved }

function pointerRay(event) {
  const rect = canvas.getBoundingClientRect();
  const ndc = new THREE.Vector2(((event.clientX - rect.left) / rect.width) * 2 - 1, -((event.clientY - rect.top) / rect.height) * 2 + 1);
  raycaster.setFromCamera(ndc, camera);
  return raycaster.ray;
}

/** What a dragged point may do, in the model's frame (`content`'s local coordinates):
 * `{ line }` (an axis through it) or `{ plane }` (a plane through it). The lock chosen
 * (or its key) wins; otherwise a slit curve's point stays in its curve's plane, a bend
 * curve's point (or end normal) in its curve's plane when the curve is planar, and
 * anything else moves in the plane facing the camera. */
function dragConstraint(data, origin) {
  if (data.helix) {
    // A helix handle moves along its line (locks do not apply: it is one number).
    const handle = helixHandles(state.scene.regions[data.region].curve).find((h) => h.what === data.helix);
    return { line: { origin, direction: handle.direction.clone().transformDirection(regionMatrix(data.region)) } };
  }
  const slitCurvePoint = state.mode === 'slit' && data.anchor === undefined;
  const lock = LOCKS[$('drag-lock').value];
  if (lock && !slitCurvePoint) {
    return lock.axis
      ? { line: { origin, direction: new THREE.Vector3(...lock.axis) } }
      : { plane: new THREE.Plane().setFromNormalAndCoplanarPoint(new THREE.Vector3(...lock.normal), origin) };
  }
  let normal = null;
  if (slitCurvePoint) {
    normal = new THREE.Vector3(...(data.curve === 'leg_curve' ? [0, 0, 1] : [1, 0, 0]));
  } else if (state.mode === 'bend' && data.region !== undefined && $('drag-lock').value === 'auto') {
    const plane = controlPlane(state.scene.regions[data.region].curve.control_points);
    if (plane) normal = plane.normal.transformDirection(regionMatrix(data.region));
  }
  if (!normal) normal = camera.getWorldDirection(new THREE.Vector3()).transformDirection(content.matrixWorld.clone().invert());
  return { plane: new THREE.Plane().setFromNormalAndCoplanarPoint(normal, origin) };
}

/** Where the pointer puts a dragged point under its constraint (model frame), or null. */
function constrainedPoint(event, constraint) {
  const ray = pointerRay(event).clone().applyMatrix4(content.matrixWorld.clone().invert());
  if (constraint.line) {
    const { origin, direction } = constraint.line;
    const onLine = new THREE.Vector3();
    ray.distanceSqToSegment(origin.clone().addScaledVector(direction, -1e7), origin.clone().addScaledVector(direction, 1e7), null, onLine);
    return onLine;
  }
  const { plane } = constraint;
  if (Math.abs(plane.normal.dot(ray.direction)) >= 0.15) return ray.intersectPlane(plane, new THREE.Vector3());
  // A plane seen (nearly) edge-on: the pointer's place in the plane facing the camera,
  // projected onto it (the direct intersection would fly off to infinity).
  const facing = new THREE.Plane().setFromNormalAndCoplanarPoint(ray.direction, plane.coplanarPoint(new THREE.Vector3()));
  const hit = ray.intersectPlane(facing, new THREE.Vector3());
  return hit && plane.projectPoint(hit, new THREE.Vector3());
}

canvas.addEventListener('pointerleave', () => { if (state.mode === 'bend' && !drag) highlightBendPiece(null); });

canvas.addEventListener('pointerdown', (event) => {
  // A drag or an orbit: the piece lit by hovering goes out (not relit at every edit).
  if (state.mode === 'bend') highlightBendPiece(null);
  // Handles exist in the bend, slit and FFD modes only.
  if (!state.scene || event.button !== 0 || !['bend', 'slit', 'ffd'].includes(state.mode)) return;
  pointerRay(event);
  // Anchors first (drawn over everything), then the curves' points, then the ridge ends.
  const hits = raycaster.intersectObjects(handles.children, false);
  // A ridge end counts only where it is seen: not behind the sheet.
  const sheetHit = raycaster.intersectObject(sheet, false)[0];
  const seen = (h) => !h.object.userData.anchorable || !sheetHit || h.distance <= sheetHit.distance + 2 * handleRadius;
  const hit = hits.find((h) => h.object.userData.anchor !== undefined)
    || hits.find((h) => h.object.userData.anchorable === undefined) || hits.find(seen);
  if (!hit) return;
  const data = hit.object.userData;
  if (data.anchorable) {
    // A click on a ridge-line end anchors it where it is.
    const scene = structuredClone(latestScene());
    scene.anchors = [...(scene.anchors || []), data.anchorable];
    commit(scene);
    return;
  }
  if (data.anchor !== undefined && event.shiftKey) {
    const scene = structuredClone(latestScene());
    scene.anchors.splice(data.anchor, 1);
    commit(scene);
    return;
  }
  // The point moves under its constraint (dragConstraint); a bend handle's place is
  // sent in its curve's own coordinates (the region's frame when the drag began).
  const origin = content.worldToLocal(hit.object.getWorldPosition(new THREE.Vector3()));
  drag = {
    ...hit.object.userData, handle: hit.object, moved: false, before: JSON.stringify(state.scene),
    constraint: dragConstraint(data, origin),
    point: origin.clone(), // where the point is now (the model's frame)
    toCurve: data.region === undefined ? null : regionMatrix(data.region).invert(),
  };
  hit.object.material = handleActive;
  controls.enabled = false;
  canvas.setPointerCapture(event.pointerId);
  render();
});

canvas.addEventListener('pointermove', (event) => {
  // Mesh mode: the piece under the pointer lights up on the model and the pattern.
  if (!drag && state.mode === 'mesh' && state.reply && $('colour').value === 'pieces' && event.buttons === 0) {
    pointerRay(event);
    const hit = raycaster.intersectObject(sheet, false)[0];
    const faces = state.reply.model.face_pieces;
    highlightPieces(hit && hit.faceIndex < faces.length ? new Set([faces[hit.faceIndex]]) : null);
    return;
  }
  // Bend mode: the piece under the pointer lights up on the pattern.
  if (!drag && state.mode === 'bend' && state.reply && state.reply.model && event.buttons === 0) {
    pointerRay(event);
    const hit = raycaster.intersectObject(sheet, false)[0];
    const faces = state.reply.model.face_pieces;
    highlightBendPiece(hit && hit.faceIndex < faces.length ? faces[hit.faceIndex] : null);
    return;
  }
  if (!drag) return;
  const started = performance.now();
  const point = constrainedPoint(event, drag.constraint);
  if (!point) return;
  drag.point = point.clone();
  drag.handle.position.copy(point);
  render();
  drag.moved = true;
  if (state.mode === 'slit') {
    const scene = structuredClone(state.scene);
    if (drag.anchor !== undefined) scene.anchors[drag.anchor].position = [point.x, point.y, point.z];
    else scene[drag.curve].control_points[drag.index] = drag.curve === 'leg_curve' ? [point.x, point.y] : [point.z, point.y];
    requestSolve(scene, started);
    return;
  }
  // FFD: the control point follows the pointer; the restoration runs on release.
  if (state.mode === 'ffd') return;
  const onCurve = point.clone().applyMatrix4(drag.toCurve);
  const position = onCurve.toArray();
  const mode = dragMode();
  // Every bend drag is an edit of the last admissible scene that stops at the boundary
  // of the admissible shapes instead of being refused.
  if (drag.helix) {
    const handle = helixHandles(state.scene.regions[drag.region].curve).find((h) => h.what === drag.helix);
    requestSolve(state.scene, started, helixEdit(drag.region, handle, onCurve));
  } else if (mode === 'move') {
    requestSolve(state.scene, started, { kind: 'move_control_point', region: drag.region, index: drag.index, position });
  } else if (mode === 'length') {
    requestSolve(state.scene, started, { kind: 'drag_preserving_length', region: drag.region, index: drag.index, position });
  } else {
    // End handles: the dragged end's position or normal; both normals are held.
    const points = state.scene.regions[drag.region].curve.control_points;
    const held = (atEnd) => endNormal(points, atEnd).toArray();
    const handle = (end) => ({ normal: held(end === 'end') });
    const edit = { kind: 'drag_end_handles', region: drag.region, start: handle('start'), end: handle('end') };
    if (drag.what === 'position') {
      edit[drag.end].position = position;
    } else {
      const origin = new THREE.Vector3(...points[drag.end === 'start' ? 0 : points.length - 1]);
      edit[drag.end].normal = onCurve.clone().sub(origin).toArray();
    }
    requestSolve(state.scene, started, edit);
  }
});

function endDrag(event) {
  if (!drag) return;
  const { before, moved } = drag;
  const released = drag;
  drag = null;
  controls.enabled = true;
  if (canvas.hasPointerCapture(event.pointerId)) canvas.releasePointerCapture(event.pointerId);
  if (state.mode === 'ffd') {
    released.handle.material = latticeMaterial;
    if (moved && released.lattice) {
      // The drag becomes a deformation of its own, restored from the last result.
      const [i, j, k] = released.lattice;
      const p = state.reply.lattice.control_points;
      const [nu, nv] = state.reply.lattice.counts;
      const at = 3 * (i + nu * (j + nv * k));
      const by = [0, 1, 2].map((a) => released.handle.position.getComponent(a) - p[at + a]);
      // On the newest scene asked for: a drag released while the last one restores
      // adds to it, it does not replace it.
      const base = (state.ffdPending && state.ffdPending.scene) || state.ffdRequested || state.scene;
      const scene = structuredClone(base);
      scene.deformations.push({ name: `drag (${i}, ${j}, ${k})`, edits: [{ move: { points: [[i, j, k]], by } }] });
      runFfd(scene);
    }
    return;
  }
  rememberWhenSettled(moved ? before : null, () => {
    drawHandles(state.scene);
    render();
  });
}
canvas.addEventListener('pointerup', endDrag);
canvas.addEventListener('pointercancel', endDrag);

// ---------------------------------------------------------------- files

function isBendScene(scene) {
  return scene && Array.isArray(scene.outline) && Array.isArray(scene.regions);
}

function isPhotoAnnotation(scene) {
  return scene && typeof scene.image === 'object' && scene.image !== null && Array.isArray(scene.curves);
}

function isFfdScene(scene) {
  return scene && typeof scene.model === 'object' && Array.isArray(scene.deformations);
}

function isSlitScene(scene) {
  return scene && typeof scene.sheet === 'object' && scene.sheet !== null && !Array.isArray(scene.sheet);
}

function load(text, path = null) {
  let scene;
  try {
    scene = JSON.parse(text);
  } catch (error) {
    showStatus('error', `not a JSON document: ${error.message}`);
    return;
  }
  const mode = isBendScene(scene) ? 'bend' : isSlitScene(scene) ? 'slit' : isFfdScene(scene) ? 'ffd' : isPhotoAnnotation(scene) ? 'photo' : null;
  if (!mode) {
    showStatus('error', 'not a bend scene (an `outline` and `regions`), a slit scene (a `sheet`), an FFD scene (a `model` and `deformations`) or a photo annotation (an `image` and `curves`)');
    return;
  }
  if (state.mode !== mode) setMode(mode);
  state.generation += 1;
  heldArrays.clear();
  // A queued edit of the last scene must not land on this one.
  state.pending = null;
  state.requested = null;
  if (mode === 'photo') photo.draft = false;
  photo.adding = null;
  photoSvg.classList.remove('adding');
  state.path = path;
  state.pathByMode[mode] = path;
  state.undo = [];
  state.redo = [];
  state.scene = null;
  framed = false;
  updateHistoryButtons();
  showStatus('busy', `solving ${path || 'the scene'}…`);
  if (mode === 'ffd') runFfd(scene, 'none');
  else requestSolve(scene);
}

/** Fills a list with `names`; when the server's listing of them was cut short by its
 * bounds (`truncated`), a last greyed entry says that more files are not listed. */
function fillSelect(select, names, truncated = false) {
  select.innerHTML = '';
  for (const name of names) {
    const option = document.createElement('option');
    option.textContent = name;
    select.append(option);
  }
  if (truncated) {
    const note = document.createElement('option');
    Object.assign(note, { disabled: true, value: '', textContent: '… more files under the root are not listed' });
    select.append(note);
  }
}


/** The served scenes per mode (recognised by content by the server), for the list. */
const scenesByMode = { bend: [], slit: [], ffd: [], photo: [] };
/** Which of the server's lists its bounds cut short (`/api/files`'s `truncated`). */
const listing = { truncated: {} };

/** The file list shows the current mode's scenes only (the mesh mode has its own list). */
function fillSceneList() {
  if (state.mode === 'mesh') return;
  const list = $('file-list');
  const kept = list.value;
  fillSelect(list, scenesByMode[state.mode] || [], listing.truncated.scenes);
  if ([...list.options].some((o) => !o.disabled && o.value === kept)) list.value = kept;
}

async function listFiles() {
  const response = await fetch('/api/files');
  const { scenes, meshes, truncated } = await response.json();
  listing.truncated = truncated || {};
  for (const mode of Object.keys(scenesByMode)) scenesByMode[mode] = (scenes && scenes[mode]) || [];
  fillSceneList();
  fillSelect($('mesh-list'), meshes, listing.truncated.meshes);
  return scenesByMode[state.mode] || [];
}

async function openFile(path) {
  const response = await fetch(`/api/files/${path.split('/').map(encodeURIComponent).join('/')}`);
  const text = await response.text();
  if (!response.ok) {
    showStatus('error', JSON.parse(text).error.message);
    return;
  }
  load(text, path);
}

$('open').addEventListener('click', () => openFile($('file-list').value));

// ---------------------------------------------------------------- mesh mode

const MESH_EXTENSIONS = ['obj', 'ply', 'stl', 'off'];
const isMeshName = (name) => MESH_EXTENSIONS.includes(name.split('.').pop().toLowerCase());
const DOWNLOADS = {
  photo: ['model.obj', 'model.glb', 'model.stl', 'pattern.svg', 'pattern.dxf', 'pattern.pdf', 'report.json'],
  ffd: ['model.obj', 'model.glb', 'model.stl', 'deformed.obj', 'deformed.glb', 'developability-before.glb', 'developability-after.glb', 'pattern.svg', 'pattern.dxf', 'pattern.pdf', 'report.json'],
  slit: ['model.obj', 'model.glb', 'model.stl', 'mould.stl', 'pattern.svg', 'pattern.dxf', 'pattern.pdf', 'report.json'],
  bend: ['model.obj', 'model.glb', 'model.stl', 'pattern.svg', 'pattern.dxf', 'pattern.pdf', 'report.json'],
  mesh: ['model.obj', 'model.glb', 'pattern.svg', 'pattern.dxf', 'pattern.pdf', 'report.json'],
};

function setMode(mode) {
  highlightBendPiece(null);
  state.generation += 1;
  heldArrays.clear();
  state.ffdPending = null;
  if (state.ffdController) state.ffdController.abort();
  photo.adding = null;
  photoSvg.classList.remove('adding');
  state.mode = mode;
  state.path = state.pathByMode[mode] || null;
  drawRegression([]);
  for (const button of document.querySelectorAll('#modes .mode')) button.classList.toggle('active', button.dataset.mode === mode);
  for (const element of document.querySelectorAll('[data-for]')) element.hidden = !element.dataset.for.split(' ').includes(mode);
  if (mode === 'photo') $('photo-editor').hidden = $('photo-pane').value !== 'photo';
  $('model-caption').textContent = {
    photo: '3D model reconstructed from the photo (the photo view shows the curves: drag their points or the symmetry and true-size marks, add, mark or delete curves).',
    ffd: '3D model: drag a purple lattice control point and release it: the panels follow and their developability is restored (Cancel stops it); orbit, pan and zoom elsewhere.',
    mesh: '3D model: each piece of the pattern in its own colour (or the angle defect at each vertex); orbit, pan and zoom; drop a mesh file here.',
    slit: '3D model: drag an orange point of the leg curve or a blue point of the seat curve (each in its own plane); click a grey ridge-line end to anchor it, drag the yellow anchor to pull the strip (shift-click removes it); orbit, pan and zoom elsewhere.',
    bend: '3D model: drag an orange control point (in end-handle mode: an end, or a green normal tip; X, Y, Z lock an axis, Shift the plane across), or a helix\'s orange radius or green pitch handle; orbit, pan and zoom elsewhere. Red: the curve of regression where it comes near the sheet. Pattern: drag the sheet\'s orange corners (double-click an edge to add one, Shift+click to delete) and the blue flat segment\'s ends. Pointing at a piece on either view lights it on both.',
  }[mode];
  fillSelect($('download'), ['Download…', ...DOWNLOADS[mode]]);
  $('download').options[0].value = '';
  if (mode !== 'mesh') fillSceneList();
  state.undo = [];
  state.redo = [];
  updateHistoryButtons();
}
for (const button of document.querySelectorAll('#modes .mode')) {
  button.addEventListener('click', () => {
    if (button.dataset.mode === state.mode) return;
    setMode(button.dataset.mode);
    // Back to what this mode showed last, or an empty view and its example selected.
    framed = false;
    state.reply = null;
    if (state.mode !== 'mesh') state.scene = state.sceneByMode[state.mode] || null;
    if (state.mode === 'mesh' && state.mesh && state.meshOptions) solveMesh(state.meshOptions);
    else if (state.mode === 'ffd' && state.scene) runFfd(state.scene, 'none');
    else if (state.mode !== 'mesh' && state.scene) requestSolve(state.scene);
    else clearView(state.mode);
  });
}

/** An empty view for a mode with nothing loaded yet; its example selected in the list. */
function clearView(mode) {
  sheet.geometry.dispose();
  sheet.geometry = new THREE.BufferGeometry();
  rulings.geometry.dispose();
  rulings.geometry = new THREE.BufferGeometry();
  handles.clear();
  handleLines.clear();
  drawPattern('');
  $('strip-gaps').innerHTML = '';
  render();
  const example = {
    bend: 'examples/bent-rectangle.json', slit: 'examples/slit/chair.json', ffd: 'examples/ffd/skirt.json', photo: 'examples/photo/coffee-cup.json', mesh: 'examples/meshes/lamp-shade.obj',
  }[mode];
  const list = mode === 'mesh' ? $('mesh-list') : $('file-list');
  if ([...list.options].some((o) => o.value === example)) list.value = example;
  showStatus('idle', `Open a ${mode === 'mesh' ? 'mesh' : `${mode} scene`}.`);
}

// The slit sheet's lengths and strip count (Tsuruta et al. Fig. 2: L1..L4, N).
const SLIT_INPUTS = { l1: 'l1_width', l2: 'l2_panel_length', l3: 'l3_strip_length', l4: 'l4_slit_width', strips: 'strip_count' };

/** Fields for the analytic curves' parameters (bend mode): each helix's radius, pitch
 * (rise per turn, `2π` times its rise per radian) and turn (degrees), each flat arc's
 * radius. A change is an edit that stops at the boundary of the admissible shapes. */
function fillCurveParameters(scene) {
  const box = $('curve-parameters');
  const fields = [];
  (scene && scene.regions ? scene.regions : []).forEach((region, k) => {
    const name = region.name || `region ${k}`;
    const curve = region.curve;
    if (curve.type === 'helix') {
      const rise = curve.rise_per_radian || 0;
      const turn = ((curve.end_angle - (curve.start_angle || 0)) * 180) / Math.PI;
      fields.push([k, name, 'radius', 'radius', curve.radius, 1]);
      fields.push([k, name, 'pitch', 'pitch', 2 * Math.PI * rise, 1]);
      fields.push([k, name, 'turn', 'turn °', turn, 5]);
    }
    if (region.flat_curve && region.flat_curve.type === 'arc') fields.push([k, name, 'arc', 'flat arc radius', region.flat_curve.radius, 1]);
  });
  box.replaceChildren(...fields.map(([k, name, what, label, value, step]) => {
    const wrapper = document.createElement('label');
    wrapper.textContent = `${name} ${label} `;
    const input = document.createElement('input');
    Object.assign(input, { type: 'number', step, value: Number(value.toPrecision(6)) });
    input.dataset.region = k;
    input.dataset.what = what;
    wrapper.appendChild(input);
    return wrapper;
  }));
  box.hidden = state.mode !== 'bend' || fields.length === 0;
}

$('curve-parameters').addEventListener('change', (event) => {
  const input = event.target;
  const value = Number(input.value);
  if (state.mode !== 'bend' || !state.scene || input.value === '' || !Number.isFinite(value)) {
    fillCurveParameters(state.scene);
    return;
  }
  const region = Number(input.dataset.region);
  const curve = state.scene.regions[region].curve;
  const edit = input.dataset.what === 'arc'
    ? { kind: 'set_flat_arc', region, radius: value }
    : { kind: 'set_helix', region };
  if (input.dataset.what === 'radius') edit.radius = value;
  if (input.dataset.what === 'pitch') edit.rise_per_radian = value / (2 * Math.PI);
  if (input.dataset.what === 'turn') edit.end_angle = (curve.start_angle || 0) + (value * Math.PI) / 180;
  editOnce(edit);
});

function fillSlitInputs(scene) {
  for (const [id, field] of Object.entries(SLIT_INPUTS)) $(id).value = scene.sheet[field];
}

for (const [id, field] of Object.entries(SLIT_INPUTS)) {
  $(id).addEventListener('change', (event) => {
    if (state.mode !== 'slit' || !state.scene) return;
    const value = Number(event.target.value);
    if (!Number.isFinite(value)) {
      fillSlitInputs(state.scene);
      return;
    }
    const scene = structuredClone(latestScene());
    scene.sheet[field] = value;
    commit(scene);
  });
}

function meshQuery(options) {
  const query = { name: state.mesh.name, charts: options.charts };
  // A mirror plane is the develop layout's only (`sheetform develop --mirror`).
  if (options.charts === 'develop' && options.mirror) query.mirror = options.mirror;
  return new URLSearchParams(query).toString();
}

/** The layout controls showing `options`: the mirror plane only for the develop layout. */
function showMeshOptions(options) {
  $('charts').value = options.charts;
  $('mirror').value = options.mirror || '';
  $('mirror').disabled = options.charts !== 'develop';
}

/** Checks and flattens the loaded mesh with `options`; a refusal keeps the last answer. */
async function solveMesh(options) {
  const generation = state.generation;
  // Only the newest request's answer is shown: an older one answering late (a layout
  // changed while another was being solved) is dropped.
  state.meshRequest = (state.meshRequest || 0) + 1;
  const request = state.meshRequest;
  state.inFlight = true;
  showStatus('busy', `${options.charts === 'develop' ? 'developing' : 'flattening'} ${state.mesh.name}…`);
  try {
    const { response, body } = await fetchReply(`/api/mesh?${meshQuery(options)}`, state.mesh.bytes);
    if (state.generation !== generation || state.mode !== 'mesh' || request !== state.meshRequest) return false;
    if (!response.ok) {
      state.refusals += 1;
      state.lastError = body.error;
      const kept = state.reply ? ' — kept the last result' : '';
      showStatus('refused', `refused (${body.error.kind.replace('_', ' ')}): ${body.error.message}${kept}`);
      return false;
    }
    state.reply = body;
    state.meshOptions = options;
    state.lastError = null;
    showMeshOptions(options);
    drawMeshModel(body);
    drawPattern(body.pattern_svg);
    render();
    showMeshReport(body);
    return true;
  } catch (error) {
    state.lastError = String(error);
    showStatus('error', `the server did not answer: ${error}`);
    return false;
  } finally {
    state.answers += 1;
    if (request === state.meshRequest) state.inFlight = false;
    window.dispatchEvent(new Event('sheetform-idle'));
  }
}

/** Loads a mesh file's bytes (a fresh history); the mesh mode is switched on. */
async function loadMesh(name, bytes, path = null) {
  if (state.mode !== 'mesh') {
    setMode('mesh');
    state.reply = null;
  }
  const previous = { mesh: state.mesh, reply: state.reply, options: state.meshOptions, undo: state.undo, redo: state.redo };
  state.mesh = { name, bytes, path };
  state.undo = [];
  state.redo = [];
  updateHistoryButtons();
  framed = false;
  if (!(await solveMesh({ charts: $('charts').value, mirror: $('mirror').value }))) {
    // A mesh the server refuses is not loaded: the last one stays.
    state.mesh = previous.mesh;
    state.reply = previous.reply;
    state.meshOptions = previous.options;
    state.undo = previous.undo;
    state.redo = previous.redo;
    updateHistoryButtons();
    framed = true;
    if (!previous.mesh) {
      // Nothing of this mode to keep: an empty view, not the other mode's model.
      const message = $('status').textContent;
      state.reply = null;
      clearView('mesh');
      showStatus('refused', message);
    }
  }
}

async function openMesh(path) {
  const response = await fetch(`/api/files/${path.split('/').map(encodeURIComponent).join('/')}`);
  if (!response.ok) {
    showStatus('error', (await response.json()).error.message);
    return;
  }
  await loadMesh(path.split('/').pop(), await response.arrayBuffer(), path);
}

$('open-mesh').addEventListener('click', () => openMesh($('mesh-list').value));
$('open-local-mesh').addEventListener('change', async (event) => {
  const file = event.target.files[0];
  if (file) await loadMesh(file.name, await file.arrayBuffer());
});
/** Lays the mesh out again with `change` made to its options; kept in the history when
 * the server answers, the controls put back when it refuses. */
function changeMeshOptions(change) {
  if (!state.mesh || !state.meshOptions) return;
  const before = JSON.stringify(state.meshOptions);
  const generation = state.generation;
  solveMesh({ ...state.meshOptions, ...change }).then((solved) => {
    if (state.generation !== generation) return;
    if (solved) {
      state.undo.push(before);
      state.redo = [];
      updateHistoryButtons();
    } else if (!state.inFlight) {
      // Refused (not superseded by a newer request): the controls show what is drawn.
      showMeshOptions(state.meshOptions || JSON.parse(before));
    }
  });
}
$('charts').addEventListener('change', (event) => changeMeshOptions({ charts: event.target.value }));
$('mirror').addEventListener('change', (event) => changeMeshOptions({ mirror: event.target.value }));
$('colour').addEventListener('change', () => {
  if (state.mode === 'mesh' && state.reply) {
    drawMeshModel(state.reply);
    render();
  }
});

// Files dropped on the 3D view: a mesh opens in mesh mode, a scene in bend mode.
const modelView = $('model-view');
modelView.addEventListener('dragover', (event) => {
  event.preventDefault();
  modelView.classList.add('dropping');
});
modelView.addEventListener('dragleave', () => modelView.classList.remove('dropping'));
modelView.addEventListener('drop', async (event) => {
  event.preventDefault();
  modelView.classList.remove('dropping');
  const file = event.dataTransfer.files[0];
  if (!file) return;
  if (isMeshName(file.name)) {
    await loadMesh(file.name, await file.arrayBuffer());
  } else if (/\.(png|jpe?g)$/i.test(file.name)) {
    await annotatePhotoFile(file);
  } else {
    setMode('bend');
    load(await file.text(), null);
  }
});
$('open-local').addEventListener('change', async (event) => {
  const file = event.target.files[0];
  if (file) load(await file.text(), null);
});

$('save').addEventListener('click', async () => {
  if (!state.scene) return;
  const path = window.prompt('Save the scene as (a path in the served directory):', state.path || 'scene.json');
  if (!path) return;
  // Saved into another directory, the scene must name its files (texture, mesh, point
  // cloud, photograph) from there: the server says which paths change, and they are
  // changed here, so the file keeps its order of fields.
  const [from, to] = [sceneDirectory(), path.split('/').slice(0, -1).join('/')];
  const [original, mode] = [state.scene, state.mode];
  let scene = original;
  const moved = [];
  if (from !== to) {
    const query = `from=${encodeURIComponent(from)}&to=${encodeURIComponent(to)}`;
    const relocation = await fetch(`/api/relocate?${query}`, { method: 'POST', body: JSON.stringify(scene) });
    const reply = await relocation.json();
    if (!relocation.ok) {
      showStatus('error', `not saved: ${reply.error.message}`);
      return;
    }
    if (reply.moves.length > 0) {
      scene = structuredClone(scene);
      for (const move of reply.moves) {
        setAt(scene, move.pointer.split('/').slice(1), move.to);
        moved.push(`${move.field} ${move.from} → ${move.to}`);
      }
    }
  }
  const response = await fetch(`/api/files/${path.split('/').map(encodeURIComponent).join('/')}`, {
    method: 'PUT', headers: { 'Content-Type': 'application/json' }, body: JSON.stringify(scene, null, 2),
  });
  if (response.ok) {
    // An edit answered meanwhile (or another mode) keeps what it set: the file holds the
    // scene as it was when saved.
    if (state.scene !== original || state.mode !== mode) {
      showStatus('ok', `saved ${path} (as it was before the last edit)`);
      listFiles();
      return;
    }
    state.generation += 1;
    heldArrays.clear();
    state.pending = null;
    state.requested = null;
    state.path = path;
    state.pathByMode[mode] = path;
    state.scene = scene;
    state.sceneByMode[mode] = scene;
    if (moved.length > 0) {
      // The history's scenes name their files from the old directory.
      state.undo = [];
      state.redo = [];
      updateHistoryButtons();
    }
    showStatus('ok', [`saved ${path}`, ...moved].join(' · '));
    listFiles();
  } else {
    showStatus('error', `not saved: ${(await response.json()).error.message}`);
  }
});

$('download').addEventListener('change', async (event) => {
  const name = event.target.value;
  event.target.value = '';
  if (!name || (state.mode === 'mesh' ? !state.meshOptions : !state.scene)) return;
  const response = state.mode === 'mesh'
    ? await fetch(`/api/mesh/file/${name}?${meshQuery(state.meshOptions)}`, { method: 'POST', body: state.mesh.bytes })
    : await post(`/api/${state.mode}/file/${name}${dirQuery()}`, JSON.stringify(state.scene));
  if (!response.ok) {
    showStatus('error', `${name}: ${(await response.json()).error.message}`);
    return;
  }
  const link = document.createElement('a');
  link.href = URL.createObjectURL(await response.blob());
  link.download = name;
  link.click();
  URL.revokeObjectURL(link.href);
});

// ---------------------------------------------------------------- for tests and scripts

/** Where a point of the 3D view appears on the page (CSS pixels). */
function pageCoordinates(point) {
  const v = point.clone().project(camera);
  const rect = canvas.getBoundingClientRect();
  return { x: rect.left + ((v.x + 1) / 2) * rect.width, y: rect.top + ((1 - v.y) / 2) * rect.height };
}

window.sheetformEditor = {
  state,
  load,
  openFile,
  openMesh,
  loadMesh,
  setMode,
  /** The page coordinates of a control point's handle. */
  handleScreenPosition(region, index) {
    const p = new THREE.Vector3(...state.scene.regions[region].curve.control_points[index]).applyMatrix4(regionMatrix(region));
    return pageCoordinates(content.localToWorld(p));
  },
  /** The page coordinates of a helix's `radius` or `pitch` handle (bend mode). */
  helixHandleScreenPosition(region, what) {
    const handle = helixHandles(state.scene.regions[region].curve).find((h) => h.what === what);
    return pageCoordinates(content.localToWorld(handle.position.clone().applyMatrix4(regionMatrix(region))));
  },
  /** A bend control point's place in the model's frame (its region's frame applied). */
  handleModelPosition(region, index) {
    return new THREE.Vector3(...state.scene.regions[region].curve.control_points[index]).applyMatrix4(regionMatrix(region)).toArray();
  },
  /** The page coordinates of control point `index` of curve `curve` (photo mode). */
  photoPointScreenPosition(curve, index) {
    const circle = photoSvg.querySelector(`circle[data-curve="${curve}"][data-index="${index}"]`);
    const box = circle.getBoundingClientRect();
    return { x: box.left + box.width / 2, y: box.top + box.height / 2 };
  },
  /** The page coordinates of a pixel of the photograph (photo mode). */
  photoPixelScreenPosition(x, y) {
    const point = new DOMPoint(x, y).matrixTransform(photoSvg.getScreenCTM());
    return { x: point.x, y: point.y };
  },
  /** The page coordinates of lattice control point (i, j, k) (FFD mode). */
  latticeScreenPosition(i, j, k) {
    const [nu, nv] = state.reply.lattice.counts;
    const p = state.reply.lattice.control_points.slice(3 * (i + nu * (j + nv * k)), 3 * (i + nu * (j + nv * k)) + 3);
    return pageCoordinates(content.localToWorld(new THREE.Vector3(...p)));
  },
  runFfd,
  /** The drawn sheet's vertex colours (`[r, g, b]` per vertex), or null when plain. */
  sheetColours() {
    const colour = sheet.geometry.getAttribute('color');
    return sheet.material.vertexColors && colour ? Array.from({ length: colour.count }, (_, v) => [colour.getX(v), colour.getY(v), colour.getZ(v)]) : null;
  },
  /** The colour of an angle defect on the colour maps of the bend and mesh modes. */
  defectColour: (g) => defectColour(g).toArray(),
  /** The page coordinates of a slit ridge-line end the reply offers to anchor, and of
   * anchor `index` of the scene. */
  anchorableScreenPosition(k) {
    return pageCoordinates(content.localToWorld(new THREE.Vector3(...state.reply.anchorable_points[k].position)));
  },
  anchorScreenPosition(index) {
    return pageCoordinates(content.localToWorld(new THREE.Vector3(...state.scene.anchors[index].position)));
  },
  /** The page coordinates of a slit curve's control point (`leg_curve` or `seat_curve`). */
  slitHandleScreenPosition(curve, index) {
    const { points } = slitCurves(state.scene).find((c) => c.curve === curve);
    return pageCoordinates(content.localToWorld(new THREE.Vector3(...points[index])));
  },
  /** The page coordinates of a handle found by its userData fields (end-handle mode). */
  handleScreenPositionWhere(match) {
    const ball = handles.children.find((h) => Object.entries(match).every(([k, v]) => h.userData[k] === v));
    return pageCoordinates(ball.getWorldPosition(new THREE.Vector3()));
  },
  endNormal: (region, atEnd) => endNormal(state.scene.regions[region].curve.control_points, atEnd).toArray(),
  curveLength: () => state.reply.report.regions.map((r) => r.curve_length_mm),
  /** Largest relative difference between a mesh edge's 3D and flat lengths. */
  isometryError() {
    const { positions: p, flat: f, triangles: t } = state.reply.model;
    let worst = 0;
    for (let k = 0; k < t.length; k += 3) {
      for (const [a, b] of [[t[k], t[k + 1]], [t[k + 1], t[k + 2]], [t[k + 2], t[k]]]) {
        const d3 = Math.hypot(p[3 * a] - p[3 * b], p[3 * a + 1] - p[3 * b + 1], p[3 * a + 2] - p[3 * b + 2]);
        const d2 = Math.hypot(f[2 * a] - f[2 * b], f[2 * a + 1] - f[2 * b + 1]);
        worst = Math.max(worst, Math.abs(d3 - d2) / Math.max(d2, 1e-300));
      }
    }
    return worst;
  },
  idle: () => !state.inFlight && !state.pending,
  /** Bend mode: the piece lit on the model and the pattern (null: none), the faces its
   * 3D overlay holds and the piece of the pattern's lit path. */
  litBendPiece() {
    const position = litPiece.geometry.getAttribute('position');
    const path = $('pattern').querySelector('#lit-piece');
    return { piece: state.litPiece ?? null, faces: position ? position.count / 3 : 0, pathPiece: path ? Number(path.dataset.meshPiece) : null };
  },
  /** Bend mode: the page coordinates of a flat point (model units) on the pattern. */
  flatScreenPosition(p) {
    const svg = $('pattern').querySelector('svg');
    const [x, y] = flatToDrawing(flatMatrix(), p);
    const q = new DOMPoint(x, y).matrixTransform(svg.getScreenCTM());
    return { x: q.x, y: q.y };
  },
  /** The page coordinates of the centroid of face `t` of the drawn model. */
  faceScreenPosition(t) {
    const { positions: p, triangles: f } = state.reply.model;
    const centre = new THREE.Vector3();
    for (let k = 0; k < 3; k++) centre.add(new THREE.Vector3(p[3 * f[3 * t + k]], p[3 * f[3 * t + k] + 1], p[3 * f[3 * t + k] + 2]));
    return pageCoordinates(content.localToWorld(centre.divideScalar(3)));
  },
};

resize();
setMode('bend');
listFiles().then((files) => {
  const first = files.find((f) => f === 'examples/bent-rectangle.json') || files[0];
  if (first) $('file-list').value = first;
});
