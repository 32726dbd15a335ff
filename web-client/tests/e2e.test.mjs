// End-to-end test of the viewer against the real server, run with node's own
// test runner: `npm run test:e2e` (which builds web-client/dist first).
//
// Starts build/bin/cgview-server on a free port with an empty data directory
// and the built client, drives Debian's chromium (software WebGL through
// SwiftShader) with playwright-core, uploads build/samples/elephant.off through
// the page's file input, and checks that the mesh is listed, reported and drawn.
// The canvas screenshot is kept in build/test-artifacts/e2e-elephant.png.
//
// Environment: CGVIEW_SERVER (default build/bin/cgview-server),
// CHROMIUM (default /usr/bin/chromium).
import { after, before, test } from 'node:test';
import assert from 'node:assert/strict';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { chromiumBin, dist, isMeshOrange, launchBrowser, pngPixels, repo, serverBin, sleep, startServer } from './harness.mjs';

const elephant = path.join(repo, 'build', 'samples', 'elephant.off');
const artifacts = path.join(repo, 'build', 'test-artifacts');

const ELEPHANT = { vertices: 2775, faces: 5558 };
const BACKGROUND = [0x1b, 0x1d, 0x22]; // src/viewer/viewer.ts

let server = null;
let browser = null;
let page = null;
let baseUrl = null;
const pageProblems = [];
let elephantId = null;

function describeProblems() {
  return pageProblems.length ? `\npage problems:\n${pageProblems.join('\n')}` : '';
}

before(async () => {
  for (const [what, file, hint] of [
    ['the server', serverBin, 'build it with `cmake --build build`'],
    ['the built web client', path.join(dist, 'index.html'), 'run `npm run build` in web-client/'],
    ['the elephant sample', elephant, 'run ./setup.sh, which copies the samples into build/samples/'],
    ['chromium', chromiumBin, 'apt-get install chromium'],
  ]) {
    assert.ok(fs.existsSync(file), `${what} is missing: ${file} (${hint})`);
  }
  fs.mkdirSync(artifacts, { recursive: true });
  server = await startServer({ tmpPrefix: 'cgview-e2e-' });
  baseUrl = server.url;

  browser = await launchBrowser();
  page = await browser.newPage({ viewport: { width: 1280, height: 800 } });
  page.on('pageerror', (e) => pageProblems.push(`pageerror: ${e.message}`));
  // A server without the jobs API answers GET /api/v1/algorithms with 404; the
  // page says so in its algorithm panel, which is not a problem for these tests.
  const noAlgorithmsApi = (status, url) => status === 404 && new URL(url).pathname === '/api/v1/algorithms';
  page.on('console', (m) => {
    if (m.type() !== 'error') return;
    if (/status of 404/.test(m.text()) && noAlgorithmsApi(404, m.location().url || 'http://x/')) return;
    pageProblems.push(`console.error: ${m.text()}`);
  });
  page.on('response', (r) => {
    if (r.status() >= 400 && !noAlgorithmsApi(r.status(), r.url())) {
      pageProblems.push(`HTTP ${r.status()}: ${r.request().method()} ${r.url()}`);
    }
  });
  page.on('requestfailed', (r) => pageProblems.push(`request failed: ${r.url()} ${r.failure()?.errorText ?? ''}`));

  await page.goto(baseUrl + '/');
  await page.waitForFunction(() => window.__cgview?.ready === true, null, { timeout: 30000 });
});

after(async () => {
  try {
    if (browser) await browser.close();
  } finally {
    if (server) await server.stop();
  }
});

// Counts mesh-coloured and background pixels of a PNG.
async function analyse(png) {
  const { data, width, height } = await pngPixels(page, png);
  const isBackground = (r, g, b) => Math.abs(r - BACKGROUND[0]) <= 6 && Math.abs(g - BACKGROUND[1]) <= 6 && Math.abs(b - BACKGROUND[2]) <= 6;
  function region(x0, y0, x1, y1) {
    let mesh = 0;
    let bg = 0;
    let n = 0;
    for (let y = Math.floor(y0); y < Math.floor(y1); ++y) {
      for (let x = Math.floor(x0); x < Math.floor(x1); ++x) {
        const i = (y * width + x) * 4;
        const [r, g, b] = [data[i], data[i + 1], data[i + 2]];
        if (isMeshOrange(r, g, b)) ++mesh;
        if (isBackground(r, g, b)) ++bg;
        ++n;
      }
    }
    return { mesh: mesh / n, background: bg / n };
  }
  // Corner patches, 2 px in from the edges (a page border may graze the edge row).
  const k = Math.max(4, Math.round(Math.min(width, height) * 0.03));
  const m = 2;
  return {
    width,
    height,
    whole: region(0, 0, width, height),
    centre: region(width * 0.25, height * 0.25, width * 0.75, height * 0.75),
    corners: [
      region(m, m, m + k, m + k),
      region(width - m - k, m, width - m, m + k),
      region(m, height - m - k, m + k, height - m),
      region(width - m - k, height - m - k, width - m, height - m),
    ],
  };
}

test('uploading the elephant through the page lists, reports and draws it', async () => {
  // Record the progress indicator's stages as they come and go.
  await page.evaluate(() => {
    const stages = (window.__stages = []);
    const root = document.getElementById('progress');
    new MutationObserver(() => {
      const stage = root.hidden ? null : root.dataset.stage;
      if (stage && stages.at(-1) !== stage) stages.push(stage);
    }).observe(root, { attributes: true, childList: true, subtree: true, characterData: true });
  });
  await page.setInputFiles('#file-input', elephant);

  await page
    .waitForFunction(() => window.__cgview.lastLoaded !== null, null, { timeout: 60000 })
    .catch(async (e) => {
      const error = await page.evaluate(() => window.__cgview.lastError);
      throw new Error(`the elephant never showed (page error: ${error}): ${e.message}${describeProblems()}\n${server.log()}`);
    });
  const state = await page.evaluate(() => window.__cgview);
  elephantId = state.lastLoaded.id;
  assert.equal(state.lastLoaded.vertices, ELEPHANT.vertices, 'vertices decoded from the Draco stream');
  assert.equal(state.lastLoaded.faces, ELEPHANT.faces, 'faces decoded from the Draco stream');
  assert.ok(state.frames > 0, 'frames rendered');
  assert.equal(state.lastError, null, 'no error shown');

  // The list entry (the server may have loaded sample meshes of its own, an
  // elephant among them: find ours by id) and the report panel.
  const item = page.locator(`#mesh-list li.mesh[data-mesh-id="${elephantId}"]`);
  await item.waitFor();
  assert.match(await item.innerText(), /elephant\.off/);
  assert.match(await item.innerText(), /2775 V · 5558 F/);
  assert.match(await item.getAttribute('class'), /selected/);
  assert.equal(await page.locator('#mesh-list li.mesh.selected').count(), 1);
  // Its thumbnail comes from the server's EGL renderer (render.png, 96 px).
  const thumb = item.locator('img.mesh-thumb');
  await thumb.waitFor();
  await page.waitForFunction(
    (id) => {
      const img = document.querySelector(`#mesh-list li.mesh[data-mesh-id="${id}"] img.mesh-thumb`);
      return img !== null && img.complete && img.naturalWidth > 0;
    },
    elephantId,
    { timeout: 30000 },
  );
  assert.equal(await thumb.evaluate((img) => img.naturalWidth), 96, 'a 96 px thumbnail');
  assert.match(await thumb.getAttribute('src'), /\/render\.png\?width=96&height=96$/);
  assert.equal((await page.locator('#report tr[data-key="vertices"] td').innerText()).trim(), '2775');
  assert.equal((await page.locator('#report tr[data-key="faces"] td').innerText()).trim(), '5558');
  const report = await page.locator('#report').innerText();
  for (const key of ['vertices', 'faces', 'edges', 'bbox min', 'bbox max', 'components', 'boundary loops', 'genus', 'manifold']) {
    assert.ok(report.includes(key), `the report panel shows "${key}":\n${report}`);
  }
  assert.ok(await page.locator('#progress').isHidden(), 'the progress indicator is gone once shown');
  assert.deepEqual(await page.evaluate(() => window.__stages), ['uploading', 'downloading', 'decoding']);

  // The picker offers what the server reads, and the report links every
  // format it writes: both from the server's list (GET /api/v1/formats).
  const formats = await page.evaluate(async () => (await (await fetch('/api/v1/formats')).json()).formats);
  const accept = (await page.locator('#file-input').getAttribute('accept')).split(',');
  for (const ext of [...formats.flatMap((f) => f.extensions), '.zip', '.mtl', '.nrrd']) assert.ok(accept.includes(ext), `the picker takes ${ext}: ${accept}`);
  const writable = formats.filter((f) => f.can_write).map((f) => f.name);
  assert.deepEqual([...writable].sort(), ['drc', 'glb', 'obj', 'off', 'ply', 'stl', 'xyz']);
  const links = page.locator('#report .downloads a');
  assert.deepEqual(await links.allInnerTexts(), writable);
  for (const [i, f] of writable.entries()) assert.match(await links.nth(i).getAttribute('href'), new RegExp(`/download\\?format=${f}$`));

  // The canvas: orange mesh in the middle, background in the corners.
  const canvas = page.locator('#viewport canvas');
  const png = await canvas.screenshot({ path: path.join(artifacts, 'e2e-elephant.png') });
  const px = await analyse(png);
  const summary = JSON.stringify(px);
  assert.ok(px.width > 200 && px.height > 200, `canvas size ${px.width}x${px.height}`);
  assert.ok(px.centre.mesh > 0.02, `mesh-coloured fraction of the centre: ${px.centre.mesh} (${summary})`);
  for (const [i, corner] of px.corners.entries()) {
    assert.ok(corner.background > 0.98, `corner ${i} is background: ${summary}`);
    assert.equal(corner.mesh, 0, `corner ${i} has no mesh pixels: ${summary}`);
  }
  assert.deepEqual(pageProblems, [], describeProblems());
});

test("a bad upload shows the server's error detail in the page", async () => {
  const dir = fs.mkdtempSync(path.join(os.tmpdir(), 'cgview-e2e-bad-'));
  try {
    const bad = path.join(dir, 'bad.off');
    fs.writeFileSync(bad, 'OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 9\n');
    // What the server says about it, asked directly.
    const direct = await fetch(`${baseUrl}/api/v1/meshes?name=probe.off`, { method: 'POST', body: fs.readFileSync(bad) });
    assert.equal(direct.status, 400, 'the server rejects a face with a missing vertex');
    const body = await direct.json();
    assert.equal(body.error, 'invalid_mesh');
    assert.ok(body.detail, 'the error has a detail');

    await page.setInputFiles('#file-input', bad);
    const message = page.locator('#messages .message.error', { hasText: 'bad.off' });
    await message.waitFor({ timeout: 15000 });
    const text = await message.innerText();
    assert.match(text, /Upload of bad\.off failed/);
    // The detail names the uploaded file, so compare the part after it.
    const tail = body.detail.replace(/^.*probe\.off:?\s*/, '');
    assert.ok(text.includes(tail), `the page shows the server's detail "${tail}":\n${text}`);
    await message.locator('button.close').click();
    await message.waitFor({ state: 'detached' });
    // The elephant stays shown.
    assert.notEqual(await page.evaluate(() => window.__cgview.lastLoaded), null);
  } finally {
    fs.rmSync(dir, { recursive: true, force: true });
    pageProblems.length = 0; // the 400 is logged by chromium as a failed resource
  }
});

test('mesh_added and mesh_deleted events from other clients update the list', async () => {
  // Another client uploads over REST: the page learns of it over the WebSocket.
  const cube = 'OFF\n8 6 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n' + '4 0 3 2 1\n4 4 5 6 7\n4 0 1 5 4\n4 1 2 6 5\n4 2 3 7 6\n4 3 0 4 7\n';
  const r = await fetch(`${baseUrl}/api/v1/meshes?name=cube.off`, { method: 'POST', body: cube });
  assert.equal(r.status, 201, await r.clone().text());
  const mesh = await r.json();
  const item = page.locator(`#mesh-list li[data-mesh-id="${mesh.id}"]`);
  await item.waitFor({ timeout: 10000 });
  assert.match(await item.innerText(), /cube\.off/);
  // The other client deletes it once the page has its thumbnail: deleted
  // while the render is on its way (a busy server), the render answers 404,
  // which the page takes (the thumbnail goes) but the problem log records.
  await page.waitForFunction(
    (id) => {
      const img = document.querySelector(`#mesh-list li.mesh[data-mesh-id="${id}"] img.mesh-thumb`);
      return img === null || (img.complete && img.dataset.fetching === undefined);
    },
    mesh.id,
    { timeout: 30000 },
  );

  const del = await fetch(`${baseUrl}/api/v1/meshes/${mesh.id}`, { method: 'DELETE' });
  assert.equal(del.status, 204);
  await item.waitFor({ state: 'detached', timeout: 10000 });
  assert.deepEqual(pageProblems, [], describeProblems());
});

test('the delete button removes the shown mesh and clears the view', async () => {
  assert.ok(elephantId, 'the first test uploaded the elephant');
  const id = elephantId;
  const item = page.locator(`#mesh-list li.mesh[data-mesh-id="${id}"]`);
  await item.locator('button.delete').click();
  await item.waitFor({ state: 'detached', timeout: 10000 });
  await page.waitForFunction(() => window.__cgview.lastLoaded === null);
  assert.match(await page.locator('#report').innerText(), /Choose a mesh/);
  // The server is asked once "Undo" is no longer offered.
  await page.waitForFunction(() => window.__cgview.pendingUndo === 0, null, { timeout: 20000 });
  const gone = async () => !(await (await fetch(`${baseUrl}/api/v1/meshes`)).json()).meshes.some((m) => m.id === id);
  for (let i = 0; i < 50 && !(await gone()); ++i) await sleep(200);
  assert.ok(await gone(), 'the server no longer has it');
  assert.deepEqual(pageProblems, [], describeProblems());
});
