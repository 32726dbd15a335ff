// What the headless-chromium benches (browser_bench.mjs, frame_bench.mjs)
// share beyond web-client/tests/harness.mjs: argument parsing, the checks for
// the server / client / chromium, the upload, the server and browser to clean
// up whatever happens, the page's problems, opening the viewer and clicking a
// mesh, and the exit code.
import fs from 'node:fs';
import path from 'node:path';
import { chromiumBin, dist, serverBin } from '../web-client/tests/harness.mjs';

// Parses [--mesh FILE] [--<count> N] with N a whole number >= min; prints the
// usage and exits 2 on anything else.
export function parseBenchArgs(argv, { name, usage, count, defaultCount, min }) {
  const fail = (message) => {
    if (message) console.error(`${name}: ${message}`);
    console.error(`usage: node bench/${name}.mjs ${usage}   (N >= ${min}, default ${defaultCount})`);
    process.exit(2);
  };
  const args = { mesh: null, [count]: defaultCount };
  for (let i = 0; i < argv.length; ++i) {
    const a = argv[i];
    const value = () => (i + 1 < argv.length ? argv[++i] : fail(`${a} needs a value`));
    if (a === '--mesh') args.mesh = value();
    else if (a === `--${count}`) {
      args[count] = Number(value());
      if (!Number.isInteger(args[count]) || args[count] < min) fail(`--${count} must be a whole number >= ${min}`);
    } else if (a === '-h' || a === '--help') fail();
    else fail(`unknown argument ${a}`);
  }
  return args;
}

// Throws when the server, the built client or chromium is missing.
export function checkPrerequisites() {
  for (const [what, file, hint] of [
    ['the server', serverBin, 'cmake --build build'],
    ['the built web client', path.join(dist, 'index.html'), 'cd web-client && npm run build'],
    ['chromium', chromiumBin, 'apt-get install chromium'],
  ]) {
    if (!fs.existsSync(file)) throw new Error(`${what} is missing: ${file} (${hint})`);
  }
}

// The mesh given with --mesh (resolved), or null when none was.
export function givenMesh(file) {
  if (!file) return null;
  if (!fs.existsSync(file)) throw new Error(`--mesh ${file}: no such file`);
  return path.resolve(file);
}

// POSTs the file as a mesh called name; the server's answer and the time it took.
export async function uploadMesh(baseUrl, file, name = path.basename(file)) {
  const body = fs.readFileSync(file);
  const t0 = performance.now();
  const r = await fetch(`${baseUrl}/api/v1/meshes?name=${encodeURIComponent(name)}`, { method: 'POST', body });
  const text = await r.text();
  if (r.status !== 201) throw new Error(`upload of ${file}: HTTP ${r.status} ${text}`);
  return { mesh: JSON.parse(text), fileBytes: body.byteLength, uploadMs: performance.now() - t0 };
}

// The server and browser a bench holds: set them here, and they are closed on
// cleanup(), on SIGINT/SIGTERM and at the end of runBench().
export const held = { server: null, browser: null };

export async function cleanup() {
  try {
    if (held.browser) await held.browser.close().catch(() => {});
  } finally {
    held.browser = null;
    if (held.server) await held.server.stop();
    held.server = null;
  }
}

for (const signal of ['SIGINT', 'SIGTERM']) process.on(signal, () => void cleanup().finally(() => process.exit(130)));

// Runs main, cleans up and exits (1 when main threw).
export async function runBench(name, main) {
  let exitCode = 0;
  try {
    await main();
  } catch (e) {
    console.error(`${name}: ${e instanceof Error ? e.message : e}`);
    exitCode = 1;
  } finally {
    await cleanup();
  }
  process.exit(exitCode);
}

// A 1280x800 page whose errors (page errors, console errors, and onConsole's
// other messages) are collected in the returned problems list.
export async function benchPage(browser, { onConsole = null } = {}) {
  const page = await browser.newPage({ viewport: { width: 1280, height: 800 } });
  const problems = [];
  page.on('pageerror', (e) => problems.push(`pageerror: ${e.message}`));
  page.on('console', (m) => {
    if (m.type() === 'error') problems.push(`console.error: ${m.text()}`);
    else if (onConsole) onConsole(m);
  });
  return { page, problems };
}

// Opens the viewer (first) or reloads it, waits for the mesh's entry in the
// list and has the page note the time of the next click in
// window.__benchClick; returns the entry, to click.
export async function meshItem(page, baseUrl, mesh, first) {
  if (first) await page.goto(`${baseUrl}/`);
  else await page.reload();
  await page.waitForFunction(() => window.__cgview?.ready === true, null, { timeout: 30_000 });
  const item = page.locator(`#mesh-list li.mesh[data-mesh-id="${mesh.id}"]`);
  await item.waitFor({ timeout: 30_000 });
  await page.evaluate(() => {
    window.__benchClick = null;
    document.addEventListener('click', () => (window.__benchClick ??= performance.now()), { capture: true });
  });
  return item;
}
