// Server time, transfer and reply size of the editor's bend requests (issue 38), without a
// browser: POSTs the bent rectangle at 1 000 rulings to /api/bend (JSON and binary arrays)
// and a control-point edit to /api/bend/edit (binary), 30 requests each, and prints medians.
//
//   sheetform serve --port 8765 --root . &     (from the repository's root)
//   node tools/edit_latency.mjs [http://127.0.0.1:8765]
import { readFileSync } from 'fs';

const base = process.argv[2] || 'http://127.0.0.1:8765';
const scene = JSON.parse(readFileSync(new URL('../examples/bent-rectangle.json', import.meta.url), 'utf8'));
scene.tessellation = { rulings: 1000 };
const median = (values) => [...values].sort((a, b) => a - b)[values.length >> 1];
const ARRAYS = 'application/vnd.sheetform.arrays';

/** One request: its time to the last byte, its size, and the server's time. */
async function request(route, body, accept) {
  const started = performance.now();
  const response = await fetch(`${base}${route}`, { method: 'POST', headers: { Accept: accept, 'Content-Type': 'application/json' }, body });
  const bytes = new Uint8Array(await response.arrayBuffer());
  const total = performance.now() - started;
  if (!response.ok) throw new Error(`${route}: ${response.status} ${new TextDecoder().decode(bytes).slice(0, 200)}`);
  let header;
  if (response.headers.get('Content-Type') === ARRAYS) {
    const length = new DataView(bytes.buffer).getUint32(4, true);
    header = JSON.parse(new TextDecoder().decode(bytes.subarray(8, 8 + length)));
  } else {
    header = JSON.parse(new TextDecoder().decode(bytes));
  }
  return { total, size: bytes.length, server: header.server_ms };
}

const point = scene.regions[0].curve.control_points[2];
const runs = { bend_json: [], bend_arrays: [], edit_arrays: [] };
for (let k = 0; k < 30; k++) {
  runs.bend_json.push(await request('/api/bend', JSON.stringify(scene), 'application/json'));
  runs.bend_arrays.push(await request('/api/bend', JSON.stringify(scene), ARRAYS));
  const position = [point[0], point[1], point[2] + (k % 2 ? 1 : -1)];
  const edit = { scene, edit: { kind: 'move_control_point', region: 0, index: 2, position }, stop_at_boundary: true };
  runs.edit_arrays.push(await request('/api/bend/edit', JSON.stringify(edit), ARRAYS));
}
const figures = Object.fromEntries(Object.entries(runs).map(([name, list]) => [name, {
  total_ms: +median(list.map((r) => r.total)).toFixed(2),
  server_ms: +median(list.map((r) => r.server)).toFixed(2),
  bytes: list[0].size,
}]));
console.log(JSON.stringify(figures));
