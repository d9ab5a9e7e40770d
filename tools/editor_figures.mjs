// The editor's pictures in the guide (docs/guide/editor.md, issue 39), taken from the real
// editor so they stay true: `sheetform serve` over the repository, driven by Debian's
// chromium through playwright-core (the editor's npm packages, apps/serve/web), writes
//   docs/images/editor-bend.png   the desk in bend mode, the model beside its pattern
//   docs/images/editor-mesh.png   the gift box's charts in mesh mode, a piece pointed at
//   docs/images/editor-photo.png  the coffee cup's curves over its photograph
//
//   cargo build --release -p sheetform-cli
//   node tools/editor_figures.mjs [target/release/sheetform]
import { spawn } from 'node:child_process';
import { createInterface } from 'node:readline';
import { createRequire } from 'node:module';
import { fileURLToPath } from 'node:url';
import { join } from 'node:path';

const repository = fileURLToPath(new URL('..', import.meta.url));
// (playwright-core is installed with the editor's packages, not at the repository's root.)
const { chromium } = createRequire(join(repository, 'apps/serve/web/package.json'))('playwright-core');
const binary = process.argv[2] || join(repository, 'target/release/sheetform');
const images = join(repository, 'docs/images');

const server = spawn(binary, ['serve', '--root', repository, '-q'], { stdio: ['ignore', 'pipe', 'inherit'] });
process.on('exit', () => server.kill('SIGKILL'));
const url = await new Promise((resolve, reject) => {
  createInterface({ input: server.stdout }).once('line', (line) => resolve(line.trim()));
  server.once('exit', (code) => reject(new Error(`sheetform serve exited with ${code}`)));
});
const browser = await chromium.launch({
  executablePath: process.env.CHROMIUM || '/usr/bin/chromium',
  args: ['--headless', '--no-sandbox', '--disable-gpu', '--use-angle=swiftshader', '--enable-unsafe-swiftshader'],
});
try {
  const page = await browser.newPage({ viewport: { width: 1200, height: 680 } });
  const errors = [];
  page.on('pageerror', (e) => errors.push(String(e)));
  await page.goto(url);
  await page.waitForFunction(() => window.sheetformEditor && document.querySelectorAll('#file-list option').length > 0);
  /** Runs `action` and waits until the server's answer to it is drawn. */
  async function answered(action) {
    const before = await page.evaluate(() => window.sheetformEditor.state.answers);
    await action();
    await page.waitForFunction((n) => window.sheetformEditor.state.answers > n && window.sheetformEditor.idle(), before);
    const state = await page.getAttribute('#status', 'data-state');
    if (state !== 'ok') throw new Error(`the editor says ${state}: ${await page.textContent('#status')}`);
  }
  /** The page as shown, once the last frame is drawn. */
  async function shoot(name) {
    await page.evaluate(() => new Promise((done) => requestAnimationFrame(() => requestAnimationFrame(done))));
    await page.screenshot({ path: join(images, name) });
    console.log(join('docs/images', name));
  }

  // Bend: the desk, its 1 m pattern fitted beside the model.
  await page.selectOption('#file-list', 'examples/desk.json');
  await answered(() => page.click('#open'));
  await shoot('editor-bend.png');

  // Mesh: the gift box in smooth charts; a piece of the pattern pointed at lights up on
  // the model (the others fade).
  await page.click('#modes .mode[data-mode="mesh"]');
  await page.waitForFunction(() => document.querySelectorAll('#mesh-list option').length > 0);
  await page.selectOption('#mesh-list', 'examples/meshes/gift-box.obj');
  await answered(() => page.click('#open-mesh'));
  await answered(() => page.selectOption('#charts', 'smooth'));
  await page.dispatchEvent('#pattern path[data-piece="1"]', 'pointerover');
  await shoot('editor-mesh.png');

  // Photo: the coffee cup's annotated curves over the photograph.
  await page.click('#modes .mode[data-mode="photo"]');
  await page.waitForFunction(() => [...document.querySelectorAll('#file-list option')].some((o) => o.value === 'examples/photo/coffee-cup.json'));
  await page.selectOption('#file-list', 'examples/photo/coffee-cup.json');
  await answered(() => page.click('#open'));
  await shoot('editor-photo.png');
  if (errors.length) throw new Error(`page errors: ${errors.join('; ')}`);
} finally {
  await browser.close();
  server.kill('SIGKILL');
}
