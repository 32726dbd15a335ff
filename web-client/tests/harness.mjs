// What the end-to-end tests and bench/browser_bench.mjs share: the paths of
// the server, the built client and chromium, starting and stopping the real
// server and a headless chromium, and reading a screenshot's pixels.
//
// Environment: CGVIEW_SERVER (default build/bin/cgview-server),
// CHROMIUM (default /usr/bin/chromium).
import { spawn } from 'node:child_process';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import { after, before, test as nodeTest } from 'node:test';
import { chromium } from 'playwright-core';

/**
 * node:test's test(), for a file whose tests ctest runs in several parts
 * (tests/web/CMakeLists.txt, PARTS): with CGVIEW_TEST_PART=K/N, the file's
 * tests in order are dealt out to N parts and this process runs part K's,
 * skipping the others.  Every test is in one part, whatever it is called.
 */
let declaredTests = 0;
export function test(name, ...rest) {
  const index = declaredTests++;
  const part = process.env.CGVIEW_TEST_PART;
  if (part) {
    const [k, n] = part.split('/').map(Number);
    if (index % n !== k - 1) return nodeTest(name, { skip: `in part ${(index % n) + 1} of ${n}` }, () => {});
  }
  return nodeTest(name, ...rest);
}

export const webClient = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '..');
export const repo = path.resolve(webClient, '..');
export const dist = path.join(webClient, 'dist');
export const serverBin = process.env.CGVIEW_SERVER ?? path.join(repo, 'build', 'bin', 'cgview-server');
export const chromiumBin = process.env.CHROMIUM ?? '/usr/bin/chromium';

export const CHROMIUM_ARGS = [
  '--use-angle=swiftshader',
  '--enable-unsafe-swiftshader',
  '--no-sandbox',
  '--disable-background-networking',
  '--disable-component-update',
  '--disable-sync',
  '--no-first-run',
  '--headless=new',
];

export const sleep = (ms) => new Promise((r) => setTimeout(r, ms));

/** Waits until the page has drawn no frame for `quietMs` (window.__cgview.frames; orbit damping has settled). */
export async function settle(page, quietMs = 400) {
  let last = -1;
  for (;;) {
    const frames = await page.evaluate(() => window.__cgview.frames);
    if (frames === last) return;
    last = frames;
    await sleep(quietMs);
  }
}

// Servers still running and data directories not yet removed: the safety net
// below deals with them if the process exits without stop().
const leftovers = new Set();

process.on('exit', () => {
  for (const { proc, dataDir } of leftovers) {
    if (proc.exitCode === null && proc.signalCode === null) proc.kill('SIGKILL');
    fs.rmSync(dataDir, { recursive: true, force: true });
  }
});

// Starts the server on a port of its choosing with an empty data directory and
// the built client; resolves once it has said where it serves and
// GET /api/v1/health answers ok.
export async function startServer({ tmpPrefix = 'cgview-', extraArgs = [], timeoutMs = 30_000 } = {}) {
  const dataDir = fs.mkdtempSync(path.join(os.tmpdir(), tmpPrefix));
  const proc = spawn(serverBin, ['--host', '127.0.0.1', '--port', '0', '--data-dir', dataDir, '--static-dir', dist, ...extraArgs], {
    cwd: repo,
    stdio: ['ignore', 'pipe', 'pipe'],
  });
  const entry = { proc, dataDir };
  leftovers.add(entry);
  let serverLog = '';
  const log = () => serverLog;
  const exited = () => proc.exitCode !== null || proc.signalCode !== null;

  let stopping = null;
  const stop = () => {
    stopping ??= new Promise((resolve) => {
      if (exited()) return resolve();
      const killer = setTimeout(() => proc.kill('SIGKILL'), 5000);
      proc.once('exit', () => {
        clearTimeout(killer);
        resolve();
      });
      proc.kill('SIGTERM');
    }).then(() => {
      fs.rmSync(dataDir, { recursive: true, force: true });
      leftovers.delete(entry);
    });
    return stopping;
  };

  try {
    const url = await new Promise((resolve, reject) => {
      const timer = setTimeout(() => reject(new Error(`cgview-server did not say where it serves within ${timeoutMs / 1000} s:\n${serverLog}`)), timeoutMs);
      const onData = (chunk) => {
        serverLog += chunk.toString();
        if (serverLog.length > 20000) serverLog = serverLog.slice(-20000);
        const m = /CGView serving (http:\/\/[^/\s]+)\//.exec(serverLog);
        if (m) {
          clearTimeout(timer);
          resolve(m[1]);
        }
      };
      proc.stdout.on('data', onData);
      proc.stderr.on('data', onData);
      proc.once('error', (e) => {
        clearTimeout(timer);
        reject(e);
      });
      proc.once('exit', (code, signal) => {
        clearTimeout(timer);
        reject(new Error(`cgview-server exited (${code ?? signal}):\n${serverLog}`));
      });
    });
    await waitForHealth(url, timeoutMs, exited, log);
    return { url, port: Number(new URL(url).port), dataDir, log, stop };
  } catch (e) {
    await stop();
    throw e;
  }
}

async function waitForHealth(url, timeoutMs, exited, log) {
  const deadline = Date.now() + timeoutMs;
  let last = '';
  while (Date.now() < deadline) {
    if (exited()) throw new Error(`cgview-server exited before it was healthy:\n${log()}`);
    try {
      const r = await fetch(`${url}/api/v1/health`);
      const body = await r.json();
      if (r.status === 200 && body.status === 'ok') return body;
      if (r.status === 401 && body.error === 'unauthorized') return body; // up, and it needs a token (--auth required)
      last = `HTTP ${r.status} ${JSON.stringify(body)}`;
    } catch (e) {
      last = e.message;
    }
    await sleep(100);
  }
  throw new Error(`GET /api/v1/health did not answer ok within ${timeoutMs} ms (last: ${last}):\n${log()}`);
}

// Debian's chromium, headless, software WebGL through SwiftShader.
export function launchBrowser() {
  return chromium.launch({ executablePath: chromiumBin, args: CHROMIUM_ARGS, headless: true });
}

// The RGBA pixels of a PNG screenshot, decoded by the page's own image
// decoder (a 2D canvas), as { width, height, data: Uint8Array (4 per pixel) }.
export async function pngPixels(page, png) {
  const { width, height, b64 } = await page.evaluate(async (src) => {
    const img = new Image();
    img.src = `data:image/png;base64,${src}`;
    await img.decode();
    const c = document.createElement('canvas');
    c.width = img.naturalWidth;
    c.height = img.naturalHeight;
    const ctx = c.getContext('2d', { willReadFrequently: true });
    ctx.drawImage(img, 0, 0);
    const { data } = ctx.getImageData(0, 0, c.width, c.height);
    const url = await new Promise((resolve) => {
      const reader = new FileReader();
      reader.onload = () => resolve(reader.result);
      reader.readAsDataURL(new Blob([data]));
    });
    return { width: c.width, height: c.height, b64: String(url).slice(String(url).indexOf(',') + 1) };
  }, png.toString('base64'));
  return { width, height, data: new Uint8Array(Buffer.from(b64, 'base64')) };
}

/**
 * A call of the server's API as the holder of `token`: { status, json (null
 * when the body is not JSON: CSV, PNG), text }. A body that is not a string
 * or a Buffer is sent as JSON.
 */
export async function apiCall(baseUrl, token, method, route, body, contentType = 'application/json') {
  const r = await fetch(baseUrl + '/api/v1' + route, {
    method,
    body: body === undefined ? undefined : typeof body === 'string' || Buffer.isBuffer(body) ? body : JSON.stringify(body),
    headers: { Authorization: `Bearer ${token}`, 'Content-Type': contentType },
  });
  const text = await r.text();
  let json = null;
  try {
    json = JSON.parse(text);
  } catch {
    // CSV, PNG
  }
  return { status: r.status, json, text };
}

/** The viewer's background (src/viewer/viewer.ts), and when two pictures of the view count as the same. */
export const VIEW_BACKGROUND = [0x1b, 0x1d, 0x22];
export const PICTURE_TOLERANCE = { meanAbs: 1.5, farShare: 0.01, far: 48 };

/**
 * How two pictures (PNG buffers of one size) differ where either shows
 * something (pixels that are background in both are left out, so that the
 * size of the mesh on the canvas does not dilute the measure): the mean
 * absolute difference per channel (RGB, 0..255), the share of those pixels
 * where a channel differs by more than PICTURE_TOLERANCE.far, their count,
 * and whether that is within PICTURE_TOLERANCE (`same`). Different sizes
 * give { sizes } alone.
 */
export async function pictureDifference(page, pngA, pngB) {
  const a = await pngPixels(page, pngA);
  const b = await pngPixels(page, pngB);
  if (a.width !== b.width || a.height !== b.height) return { sizes: [`${a.width}x${a.height}`, `${b.width}x${b.height}`], same: false };
  const bg = VIEW_BACKGROUND;
  const background = (d, i) => Math.abs(d[i] - bg[0]) <= 6 && Math.abs(d[i + 1] - bg[1]) <= 6 && Math.abs(d[i + 2] - bg[2]) <= 6;
  let sum = 0;
  let far = 0;
  let n = 0;
  for (let i = 0; i < a.data.length; i += 4) {
    if (background(a.data, i) && background(b.data, i)) continue;
    ++n;
    let worst = 0;
    for (let k = 0; k < 3; ++k) {
      const d = Math.abs(a.data[i + k] - b.data[i + k]);
      sum += d;
      worst = Math.max(worst, d);
    }
    if (worst > PICTURE_TOLERANCE.far) ++far;
  }
  const d = { meanAbs: sum / (3 * Math.max(1, n)), farShare: far / Math.max(1, n), pixels: n };
  return { ...d, same: d.meanAbs < PICTURE_TOLERANCE.meanAbs && d.farShare < PICTURE_TOLERANCE.farShare };
}

// The surface's plain colour (#e07a1f, hue 28°) under white light: an orange
// hue, clearly saturated, not too dark; highlights whiten and do not count.
export function isMeshOrange(r, g, b) {
  const max = Math.max(r, g, b);
  const min = Math.min(r, g, b);
  if (max < 40 || max - min < 0.35 * max || r !== max) return false;
  const hue = (60 * (g - b)) / (max - min);
  return hue >= 12 && hue <= 45;
}

// Distinct hues among the saturated pixels of the canvas, in 30° buckets
// holding at least 1% of them (a colour map shows several), and the share of the plain orange surface.
export function hueStats({ data }) {
  const buckets = new Array(12).fill(0);
  let saturated = 0;
  let orange = 0;
  for (let i = 0; i < data.length; i += 4) {
    const [r, g, b] = [data[i], data[i + 1], data[i + 2]];
    const max = Math.max(r, g, b);
    const min = Math.min(r, g, b);
    if (max < 40 || max - min < 0.25 * max) continue;
    let h;
    if (max === r) h = (60 * (g - b)) / (max - min);
    else if (max === g) h = 120 + (60 * (b - r)) / (max - min);
    else h = 240 + (60 * (r - g)) / (max - min);
    h = (h + 360) % 360;
    ++saturated;
    ++buckets[Math.floor(h / 30) % 12];
    if (max === r && h >= 12 && h <= 45 && max - min >= 0.35 * max) ++orange;
  }
  const distinct = buckets.filter((n) => n >= 0.01 * saturated).length;
  return { saturated, distinct, buckets, orange: saturated ? orange / saturated : 0 };
}

export const artifactsDir = path.join(repo, 'build', 'test-artifacts');

// The set-up the end-to-end tests share: checks that the server, the built
// client, chromium and `mesh` exist; starts the server, chromium and a page
// on the viewer, recording the page's errors (and HTTP errors with
// httpErrors) in `problems`; with `mesh`, uploads it and shows it;
// serverArgs are added to the server's command line.
// Returns { server, browser, page, problems, describeProblems, meshId, close }.
export async function openViewer({ tmpPrefix, mesh = null, httpErrors = true, serverArgs = [] }) {
  const files = [
    ['the server', serverBin],
    ['the built web client', path.join(dist, 'index.html')],
    ['chromium', chromiumBin],
  ];
  if (mesh) files.push(['the mesh', mesh]);
  for (const [what, file] of files) {
    if (!fs.existsSync(file)) throw new Error(`${what} is missing: ${file}`);
  }
  fs.mkdirSync(artifactsDir, { recursive: true });
  const server = await startServer({ tmpPrefix, extraArgs: serverArgs });
  const browser = await launchBrowser();
  const page = await browser.newPage({ viewport: { width: 1280, height: 800 } });
  const problems = [];
  page.on('pageerror', (e) => problems.push(`pageerror: ${e.message}`));
  page.on('console', (m) => {
    if (m.type() === 'error') problems.push(`console.error: ${m.text()} (${m.location().url})`);
  });
  if (httpErrors) {
    page.on('response', (r) => {
      if (r.status() >= 400) problems.push(`HTTP ${r.status()}: ${r.request().method()} ${r.url()}`);
    });
  }
  const describeProblems = () => (problems.length ? `\npage problems:\n${problems.join('\n')}` : '');
  await page.goto(server.url + '/');
  await page.waitForFunction(() => window.__cgview?.ready === true, null, { timeout: 30000 });
  let meshId = null;
  if (mesh) {
    const r = await fetch(`${server.url}/api/v1/meshes?name=${encodeURIComponent(path.basename(mesh))}`, {
      method: 'POST',
      body: fs.readFileSync(mesh),
    });
    if (r.status !== 201) throw new Error(`uploading ${mesh}: HTTP ${r.status} ${await r.text()}`);
    meshId = (await r.json()).id;
    await page.locator(`#mesh-list li.mesh[data-mesh-id="${meshId}"]`).click();
    await page.waitForFunction((id) => window.__cgview.lastLoaded?.id === id, meshId, { timeout: 60000 });
  }
  const close = async () => {
    try {
      await browser.close();
    } finally {
      await server.stop();
    }
  };
  return { server, browser, page, problems, describeProblems, meshId, close };
}

// openViewer() for a test file: registers the node:test hooks that open the
// viewer before its tests and close it after them, and returns the object
// they fill in ({ server, page, problems, describeProblems, meshId, ... }).
export function useViewer(options) {
  const v = {};
  before(async () => {
    Object.assign(v, await openViewer(options));
  });
  after(async () => {
    if (v.close) await v.close();
  });
  return v;
}

/** Submits a job through the API; resolves with its id (asserts 201). */
export async function submitJob(v, algorithm, inputs, params = {}) {
  const r = await fetch(`${v.server.url}/api/v1/jobs`, { method: 'POST', body: JSON.stringify({ algorithm, inputs, params }) });
  if (r.status !== 201) throw new Error(`POST /jobs ${algorithm}: HTTP ${r.status} ${await r.text()}`);
  return (await r.json()).id;
}

/** The job's row in the Jobs panel once it shows done. */
export async function doneRow(v, jobId) {
  const li = v.page.locator(`#jobs li.job[data-job-id="${jobId}"][data-state="done"]`);
  await li.waitFor({ timeout: 120000 }).catch(async (e) => {
    const job = await (await fetch(`${v.server.url}/api/v1/jobs/${jobId}`)).json();
    throw new Error(`job ${jobId} never showed done: ${e.message}\n${JSON.stringify(job)}${v.describeProblems()}`);
  });
  return li;
}

/** Significant digits of a number as written ("0.001235" → 4, "-175" → 3, "22460" → 4, "1.2e-7" → 2). */
export function significantDigits(text) {
  let mantissa = text.replace(/^-/, '').replace(/e.*$/i, '');
  // A whole number's trailing zeros only place it ("22460" is 2.246e4).
  if (!mantissa.includes('.')) mantissa = mantissa.replace(/0+$/, '');
  return mantissa.replace('.', '').replace(/^0+/, '').length;
}

/** Throws unless `text` is a number of at most four significant digits; returns it. */
export function shortNumber(text, what) {
  if (!/^-?[0-9.]+(e[-+]?[0-9]+)?$/.test(text)) throw new Error(`${what} is not a number: "${text}"`);
  if (significantDigits(text) > 4) throw new Error(`${what} has more than 4 significant digits: "${text}"`);
  return Number(text);
}

/** An axis-aligned box of sides sx, sy, sz about the origin, its faces turned outwards: its corners and 12 triangles (0-based). */
export function boxCorners(sx = 1, sy = 1, sz = 1) {
  const corners = [];
  for (let i = 0; i < 8; ++i) corners.push([(i & 1 ? 0.5 : -0.5) * sx, (i & 2 ? 0.5 : -0.5) * sy, (i & 4 ? 0.5 : -0.5) * sz]);
  const quads = [
    [0, 2, 3, 1],
    [4, 5, 7, 6],
    [0, 1, 5, 4],
    [2, 6, 7, 3],
    [0, 4, 6, 2],
    [1, 3, 7, 5],
  ];
  return {
    corners,
    triangles: quads.flatMap(([a, b, c, d]) => [
      [a, b, c],
      [a, c, d],
    ]),
  };
}

/** The box of boxCorners as OFF text. */
export function boxOff(sx = 1, sy = 1, sz = 1) {
  const { corners, triangles } = boxCorners(sx, sy, sz);
  return `OFF\n8 12 0\n${corners.map((p) => p.join(' ')).join('\n')}\n${triangles.map((t) => `3 ${t.join(' ')}`).join('\n')}\n`;
}

/** Drags the left button across the canvas from its middle by (dx, dy) pixels, as a user orbits. */
export async function orbitDrag(page, dx, dy) {
  const box = await page.locator('#viewport canvas').boundingBox();
  const cx = box.x + box.width / 2;
  const cy = box.y + box.height / 2;
  await page.mouse.move(cx, cy);
  await page.mouse.down();
  await page.mouse.move(cx + dx, cy + dy, { steps: 8 });
  await page.mouse.up();
}
