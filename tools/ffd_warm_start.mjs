// Server time of an FFD drag in the web editor, cold against warm (docs/benchmarks-history.md,
// session 20):
//
//   node tools/ffd_warm_start.mjs target/release/sheetform . skirt
//
// Five times each: a fresh `sheetform serve` restores the example with a 5 mm drag of
// lattice control point (1, 1, 0) appended (cold: every deformation), and another fresh
// server restores the example, then the same scene with the drag (warm: the drag's
// deformation alone, resumed from the server's last design). Prints the `server_ms` of
// the drag's reply for both, as JSON.
import { spawn } from 'node:child_process';
import { createInterface } from 'node:readline';
import { readFileSync } from 'node:fs';

const [binary, repository, name] = process.argv.slice(2);
if (!binary || !repository || !name) throw new Error('usage: ffd_warm_start.mjs SHEETFORM_BINARY REPOSITORY EXAMPLE');

function start() {
  const server = spawn(binary, ['serve', '--root', repository, '-q'], { stdio: ['ignore', 'pipe', 'inherit'] });
  return new Promise((resolve) => createInterface({ input: server.stdout }).once('line', (url) => resolve({ server, url: url.trim() })));
}

async function ffd(url, scene) {
  const text = await (await fetch(`${url}api/ffd`, { method: 'POST', body: JSON.stringify(scene) })).text();
  const last = JSON.parse(text.trim().split('\n').at(-1));
  if (!last.result) throw new Error(text.slice(-300));
  return last.result;
}

const base = JSON.parse(readFileSync(`${repository}/examples/ffd/${name}.json`, 'utf8'));
const drag = structuredClone(base);
drag.deformations.push({ name: 'drag (1, 1, 0)', edits: [{ move: { points: [[1, 1, 0]], by: [5, 0, 0] } }] });
const cold = [];
const warm = [];
for (let run = 0; run < 5; run++) {
  let { server, url } = await start();
  cold.push((await ffd(url, drag)).server_ms);
  server.kill();
  ({ server, url } = await start());
  await ffd(url, base);
  const reply = await ffd(url, drag);
  if (reply.resumed_deformations !== base.deformations.length) throw new Error('the drag was not resumed');
  warm.push(reply.server_ms);
  server.kill();
}
const median = (xs) => [...xs].sort((a, b) => a - b)[Math.floor(xs.length / 2)];
console.log(JSON.stringify({ name, cold_ms: cold.map(Math.round), warm_ms: warm.map(Math.round), cold_median: median(cold), warm_median: median(warm) }));
