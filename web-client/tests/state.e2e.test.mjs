// End-to-end test of the state that survives, against the real server and
// Debian's chromium:
//   CGVIEW_SERVER=build/bin/cgview-server CGVIEW_SAMPLES=build/samples node --test tests/state.e2e.test.mjs
//
// Messages: a notice goes by itself, an error stays until dismissed, and
// neither covers the 3D view. The address bar follows the view (camera
// orbited, display mode chosen) with no token in it, and a reload shows the
// same view; another mesh shown, or a comparison entered, makes a history
// entry that Back leaves. "Play" on an animation plays it: the frames
// advance with no further input, and it says "Pause" meanwhile. "Z up" turns
// a box that is tall in Z upright on screen, and the mesh keeps it after a
// reload. "Fit each pane" frames a 1-unit box and a 1000-unit one side by
// side each in its own pane. The pictures of the last two are kept in
// build/test-artifacts/e2e-state-*.png.
//
// Environment: CGVIEW_SERVER, CGVIEW_SAMPLES (default build/samples), CHROMIUM.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import fs from 'node:fs';
import path from 'node:path';
import { artifactsDir, boxOff, orbitDrag, pngPixels, repo, settle, sleep, useViewer } from './harness.mjs';

const samples = process.env.CGVIEW_SAMPLES ?? path.join(repo, 'build', 'samples');
const v = useViewer({ tmpPrefix: 'cgview-state-' });
/** How long a notice stays (panels/messages.ts), and a margin. */
const NOTICE_MS = 5000;
const MARGIN_MS = 2500;

async function upload(name, body) {
  const r = await fetch(`${v.server.url}/api/v1/meshes?name=${encodeURIComponent(name)}`, { method: 'POST', body });
  assert.equal(r.status, 201, await r.clone().text());
  return (await r.json()).id;
}

/** Shows the mesh as a click in the mesh list does, and waits for its first frame. */
async function show(id) {
  const { page } = v;
  await page.locator(`#mesh-list li.mesh[data-mesh-id="${id}"]`).click();
  await page.waitForFunction((m) => window.__cgview.lastLoaded?.id === m, id, { timeout: 60000 });
  await settle(page);
}

/** The view the page's address holds: the view link's state and the hash's other parameters. */
function addressView(url) {
  const params = new URLSearchParams(new URL(url).hash.slice(1));
  const b64 = params.get('view');
  return { state: b64 ? JSON.parse(Buffer.from(b64, 'base64url').toString()) : null, params };
}

/** Waits until the address holds a view for which `check(state, params)` is true; returns it. */
async function waitForAddress(check, what, timeoutMs = 10000) {
  const deadline = Date.now() + timeoutMs;
  for (;;) {
    const url = v.page.url();
    const view = addressView(url);
    if (view.state && check(view.state, view.params)) return { url, ...view };
    if (Date.now() > deadline) throw new Error(`the address never held ${what}: ${url}`);
    await sleep(100);
  }
}

const near = (a, b, eps = 1e-6) => a.length === b.length && a.every((x, i) => Math.abs(x - b[i]) <= eps * Math.max(1, Math.abs(b[i])));

/** The canvas as drawn (with what lies over it), as pixels. */
async function canvasPixels() {
  return pngPixels(v.page, await v.page.locator('#viewport canvas').screenshot());
}

/** Whether a pixel is drawn: away from the background, #1b1d22. */
function drawn(data, i) {
  return Math.abs(data[i] - 0x1b) + Math.abs(data[i + 1] - 0x1d) + Math.abs(data[i + 2] - 0x22) > 40;
}

/** The box of the drawn pixels in [x0, x1) × [y0, y1): { width, height, count }. */
function drawnBox({ width, data }, x0, y0, x1, y1) {
  let minX = Infinity;
  let minY = Infinity;
  let maxX = -Infinity;
  let maxY = -Infinity;
  let count = 0;
  for (let y = y0; y < y1; ++y) {
    for (let x = x0; x < x1; ++x) {
      if (!drawn(data, 4 * (y * width + x))) continue;
      ++count;
      minX = Math.min(minX, x);
      maxX = Math.max(maxX, x);
      minY = Math.min(minY, y);
      maxY = Math.max(maxY, y);
    }
  }
  return count ? { width: maxX - minX + 1, height: maxY - minY + 1, count } : { width: 0, height: 0, count: 0 };
}

function intersects(a, b) {
  return a.x < b.x + b.width && b.x < a.x + a.width && a.y < b.y + b.height && b.y < a.y + a.height;
}

let cube = null;
let ico = null;

test('a notice goes by itself, an error stays until dismissed, and no message covers the view', async () => {
  const { page } = v;
  await page.getByRole('button', { name: 'Copy link', exact: true }).click();
  const error = page.getByRole('alert').filter({ hasText: 'Choose a mesh first' });
  await error.waitFor({ timeout: 5000 });

  cube = await upload('cube.off', fs.readFileSync(path.join(samples, 'cube.off')));
  await show(cube);
  await page.getByRole('button', { name: 'Copy link', exact: true }).click();
  const notice = page.getByRole('status').filter({ hasText: 'View link' });
  await notice.waitFor({ timeout: 5000 });

  const canvas = await page.locator('#viewport canvas').boundingBox();
  for (const m of await page.locator('#messages .message').all()) {
    const r = await m.boundingBox();
    assert.ok(r && !intersects(r, canvas), `a message over the view: ${JSON.stringify(r)} and the canvas ${JSON.stringify(canvas)}`);
  }

  await sleep(NOTICE_MS + MARGIN_MS);
  assert.equal(await notice.count(), 0, 'the notice went by itself');
  assert.ok(await error.isVisible(), 'the error stays');
  await error.getByRole('button', { name: 'Dismiss' }).click();
  await error.waitFor({ state: 'detached', timeout: 2000 });
  assert.deepEqual(v.problems, [], v.describeProblems());
});

test('the address follows the view, holds no token, and a reload shows the same view', async () => {
  const { page } = v;
  await orbitDrag(page, 80, 30);
  await settle(page);
  const camera = await page.evaluate(() => window.__cgview.camera());
  await waitForAddress((s) => s.mesh === cube && near(s.camera.position, camera.position), 'the orbited camera');

  await page.getByLabel('Display mode').selectOption('wireframe');
  const { url, state } = await waitForAddress((s) => s.display?.mode === 'wireframe', 'the wireframe mode');
  assert.ok(!/token|bearer|authorization/i.test(decodeURIComponent(url)), `no credential in the address: ${url}`);
  assert.ok(near(state.camera.position, camera.position), 'the camera is kept');

  await page.reload();
  await page.waitForFunction(() => window.__cgview?.viewRestored != null, null, { timeout: 60000 });
  const restored = await page.evaluate(() => window.__cgview.viewRestored);
  assert.ok(!restored.error, `restoring failed: ${restored.error}`);
  assert.ok(near(restored.camera.position, state.camera.position), `camera ${restored.camera.position} vs ${state.camera.position}`);
  assert.ok(near(restored.camera.target, state.camera.target), `target ${restored.camera.target} vs ${state.camera.target}`);
  assert.equal(restored.mode, 'wireframe');
  assert.equal(await page.getByLabel('Display mode').inputValue(), 'wireframe', 'the panel shows the mode');
  assert.equal(await page.evaluate(() => window.__cgview.lastLoaded?.id), cube);
  assert.deepEqual(v.problems, [], v.describeProblems());
});

test("a skeleton drawn and a grid's slices are kept in the address, and a reload shows them again", async () => {
  const { page } = v;
  /** Data for the cube, uploaded as another tool's file: its import job, done. */
  const importData = async (name, body) => {
    const r = await fetch(`${v.server.url}/api/v1/data?name=${encodeURIComponent(name)}&mesh=${cube}`, { method: 'POST', body });
    assert.equal(r.status, 201, await r.clone().text());
    return r.json();
  };
  const bone = await importData('bone.polylines.txt', '2 0 -0.4 0 0 0.4 0\n');
  const header = 'NRRD0004\ntype: uchar\ndimension: 3\nsizes: 2 2 2\nencoding: raw\n\n';
  const grid = await importData('two.nrrd', Buffer.concat([Buffer.from(header, 'ascii'), Buffer.from([0, 1, 0, 1, 0, 1, 0, 1])]));
  const keys = [bone, grid].map((j) => `${j.id}/${j.artifacts[0].name}`);
  await page.waitForFunction((ids) => ids.every((id) => document.querySelector(`#jobs li.job[data-job-id="${id}"]`)), [bone.id, grid.id], { timeout: 15000 });
  // A link that shows them (as a notebook's view of such a job opens the viewer), then a reload.
  const { url } = await waitForAddress((s) => s.mesh === cube, 'the cube');
  await page.goto(`${url.split('&show=')[0]}&${keys.map((k) => `show=${encodeURIComponent(k)}`).join('&')}`);
  await page.reload();
  await page.waitForFunction(() => window.__cgview?.viewRestored != null, null, { timeout: 60000 });
  const restored = await page.evaluate(() => window.__cgview.viewRestored);
  assert.ok(!restored.error, `restoring failed: ${restored.error}`);
  await page.waitForFunction((k) => window.__cgview.skeletons.some((s) => s.key === k), keys[0], { timeout: 15000 });
  const skeleton = (await page.evaluate(() => window.__cgview.skeletons)).find((s) => s.key === keys[0]);
  assert.deepEqual([skeleton.nodes, skeleton.edges], [2, 1], 'the bone drawn');
  const panel = page.locator('#voxel-slices');
  await panel.waitFor({ state: 'visible', timeout: 10000 });
  assert.equal(await panel.locator('h2').textContent(), 'Slices of grid');
  // The address keeps them: the view written again holds both.
  const again = await waitForAddress((_, params) => params.getAll('show').length === 2, 'the shown skeleton and grid');
  assert.deepEqual(again.params.getAll('show'), keys);
  // Hidden, they leave the address.
  await panel.getByRole('button', { name: /close/i }).click();
  await waitForAddress((_, params) => !params.getAll('show').includes(keys[1]), 'the grid closed');
  assert.deepEqual(v.problems, [], v.describeProblems());
});

test('another mesh, or a comparison, makes a history entry: Back returns to the view before it', async () => {
  const { page } = v;
  await settle(page);
  const before = await waitForAddress((s) => s.mesh === cube, 'the cube');
  ico = await upload('icosahedron.off', fs.readFileSync(path.join(samples, 'icosahedron.off')));
  await show(ico);
  await waitForAddress((s) => s.mesh === ico, 'the icosahedron');

  await page.goBack();
  await page.waitForFunction((id) => window.__cgview.lastLoaded?.id === id && window.__cgview.viewRestored?.camera, cube, { timeout: 60000 });
  const restored = await page.evaluate(() => window.__cgview.viewRestored);
  assert.ok(near(restored.camera.position, before.state.camera.position), `camera ${restored.camera.position} vs ${before.state.camera.position}`);
  assert.equal(restored.mode, 'wireframe');
  assert.equal(addressView(page.url()).state.mesh, cube);

  // The icosahedron beside the cube, then side by side: Back leaves the panes, Forward shows them again.
  await page.getByRole('button', { name: 'Add icosahedron.off to the scene', exact: true }).click();
  await page.waitForFunction((id) => window.__cgview.scene.objects[1]?.mesh === id && window.__cgview.scene.objects[1].loaded, ico, { timeout: 30000 });
  await waitForAddress((s) => s.scene?.length === 2 && !s.panes, 'the scene of two');
  await page.locator('#scene').getByRole('button', { name: 'Side by side', exact: true }).click();
  await page.waitForFunction(() => window.__cgview.scene.panes === 2);
  await waitForAddress((s) => s.panes === true, 'the panes');
  await page.goBack();
  await page.waitForFunction(() => window.__cgview.scene.panes === 0 && window.__cgview.scene.objects.length === 2, null, { timeout: 30000 });
  await waitForAddress((s) => s.scene?.length === 2 && !s.panes, 'the scene of two, back');
  await page.goForward();
  await page.waitForFunction(() => window.__cgview.scene.panes === 2, null, { timeout: 30000 });
  await page.getByRole('button', { name: 'Leave comparison', exact: true }).click();
  await page.waitForFunction(() => window.__cgview.scene.panes === 0);
  assert.deepEqual(v.problems, [], v.describeProblems());
});

test('"Play" plays an animation: the frames advance with no further input, and it says "Pause" meanwhile', async () => {
  const { page, server } = v;
  const elephant = await upload('elephant.off', fs.readFileSync(path.join(samples, 'elephant.off')));
  await show(elephant);
  await page.getByLabel('Display mode').selectOption('smooth');
  const r = await fetch(`${server.url}/api/v1/jobs`, { method: 'POST', body: JSON.stringify({ algorithm: 'chaos_animate', inputs: { mesh: elephant }, params: { frames: 40 } }) });
  assert.equal(r.status, 201, await r.clone().text());
  const job = (await r.json()).id;
  const row = page.locator(`#jobs li.job[data-job-id="${job}"][data-state="done"] .artifact-animation`);
  await row.waitFor({ timeout: 120000 });
  await row.getByRole('button', { name: 'Play', exact: true }).click();
  await page.waitForFunction(() => window.__cgview.lastAnimation !== null, null, { timeout: 30000 });
  await row.getByRole('button', { name: 'Pause', exact: true }).waitFor({ timeout: 5000 });
  assert.equal(await page.locator('#animation-player button.player-play').innerText(), 'Pause');
  const first = await page.evaluate(() => window.__cgview.lastAnimation.frame);
  const pixels = await canvasPixels();
  await sleep(1000);
  const later = await page.evaluate(() => window.__cgview.lastAnimation.frame);
  assert.ok(later > first, `the frames advance by themselves: ${first} then ${later}`);
  const after = await canvasPixels();
  let changed = 0;
  for (let i = 0; i < pixels.data.length; i += 4) if (drawn(pixels.data, i) !== drawn(after.data, i)) ++changed;
  assert.ok(changed > 50, `the picture changes as it plays: ${changed} pixels`);

  await row.getByRole('button', { name: 'Pause', exact: true }).click();
  await row.getByRole('button', { name: 'Play', exact: true }).waitFor({ timeout: 5000 });
  // The hook is set once a frame is drawn: the frame the player last went to
  // may be drawn just after the pause.
  await page.waitForFunction(() => window.__cgview.lastAnimation.frame === Number(document.querySelector('#animation-player .player-slider').value), null, { timeout: 5000 });
  const paused = await page.evaluate(() => window.__cgview.lastAnimation.frame);
  await sleep(600);
  assert.equal(await page.evaluate(() => window.__cgview.lastAnimation.frame), paused, 'paused, it stays on its frame');
  assert.equal(await page.locator('#animation-player button.player-play').innerText(), 'Play');
  assert.deepEqual(v.problems, [], v.describeProblems());
});

test('"Z up" stands a box that is tall in Z upright, and the mesh keeps it after a reload', async () => {
  const { page } = v;
  const tall = await upload('tall-z.off', boxOff(1, 1, 4));
  await show(tall);
  const { width, height } = await canvasPixels();
  const lying = drawnBox(await canvasPixels(), 0, 0, width, height);
  const up = page.getByLabel('Up axis');
  assert.equal(await up.inputValue(), 'y', 'Y up unless chosen');
  assert.ok(lying.height < 1.3 * lying.width, `Y up, the box lies: ${JSON.stringify(lying)}`);

  await up.selectOption('z');
  await page.waitForFunction(() => window.__cgview.display?.up === 'z');
  await settle(page);
  const standing = drawnBox(await canvasPixels(), 0, 0, width, height);
  await page.locator('#viewport canvas').screenshot({ path: path.join(artifactsDir, 'e2e-state-z-up.png') });
  assert.ok(standing.height > 1.6 * standing.width, `Z up, the box stands: ${JSON.stringify(standing)}`);
  await waitForAddress((s, p) => s.mesh === tall && p.get('up') === 'z', 'the Z axis up');

  await page.reload();
  await page.waitForFunction(() => window.__cgview?.viewRestored != null, null, { timeout: 60000 });
  await settle(page);
  assert.equal(await page.getByLabel('Up axis').inputValue(), 'z', 'the panel shows Z up');
  const again = drawnBox(await canvasPixels(), 0, 0, width, height);
  assert.ok(again.height > 1.6 * again.width, `after a reload, the box still stands: ${JSON.stringify(again)}`);

  // Another mesh keeps its own axis; back on the box, Z up again (kept for that mesh).
  await show(cube);
  assert.equal(await page.getByLabel('Up axis').inputValue(), 'y', 'the cube is Y up');
  await show(tall);
  assert.equal(await page.getByLabel('Up axis').inputValue(), 'z', 'the box is still Z up');
  const shown = drawnBox(await canvasPixels(), 0, 0, width, height);
  assert.ok(shown.height > 1.6 * shown.width, `shown again, it stands: ${JSON.stringify(shown)}`);
  assert.deepEqual(v.problems, [], v.describeProblems());
});

test('"Fit each pane" frames a 1-unit box and a 1000-unit box side by side each in its pane', async () => {
  const { page } = v;
  const small = await upload('small.off', boxOff(1, 1, 1));
  await upload('big.off', boxOff(1000, 1000, 1000));
  await show(small);
  await page.getByRole('button', { name: 'Add big.off to the scene', exact: true }).click();
  await page.waitForFunction(() => window.__cgview.scene.objects[1]?.loaded, null, { timeout: 30000 });
  await page.locator('#scene').getByRole('button', { name: 'Side by side', exact: true }).click();
  await page.waitForFunction(() => window.__cgview.scene.panes === 2);
  await settle(page);

  // The share of each pane drawn, away from its title above and the options below.
  const coverage = async () => {
    const pixels = await canvasPixels();
    const half = Math.floor(pixels.width / 2);
    return [0, 1].map((i) => {
      const [x0, x1, y0, y1] = [i * half + 8, (i + 1) * half - 8, 50, pixels.height - 60];
      return drawnBox(pixels, x0, y0, x1, y1).count / ((x1 - x0) * (y1 - y0));
    });
  };
  const together = await coverage();
  assert.ok(together[0] < 0.01 && together[1] > 0.05, `framed together, the small box is a dot: ${together}`);

  const fit = page.getByRole('button', { name: 'Fit each pane', exact: true });
  await fit.click();
  await settle(page);
  assert.equal(await fit.getAttribute('aria-pressed'), 'true');
  const each = await coverage();
  await page.locator('#viewport canvas').screenshot({ path: path.join(artifactsDir, 'e2e-state-fit-each-pane.png') });
  assert.ok(
    each.every((c) => c > 0.05),
    `each pane framed on its box: ${each}`,
  );
  assert.ok(Math.abs(each[0] - each[1]) < 0.5 * Math.max(...each), `the two boxes fill their panes alike: ${each}`);

  // Orbiting moves both panes alike: each box still fills its pane.
  const box = await page.locator('#viewport canvas').boundingBox();
  await page.mouse.move(box.x + box.width / 4, box.y + box.height / 2);
  await page.mouse.down();
  await page.mouse.move(box.x + box.width / 4 + 60, box.y + box.height / 2 + 20, { steps: 6 });
  await page.mouse.up();
  await settle(page);
  const orbited = await coverage();
  assert.ok(
    orbited.every((c) => c > 0.05),
    `after orbiting, each pane still framed: ${orbited}`,
  );

  await fit.click();
  await settle(page);
  assert.equal(await fit.getAttribute('aria-pressed'), 'false');
  const again = await coverage();
  assert.ok(again[0] < 0.01, `framed together again: ${again}`);
  await page.getByRole('button', { name: 'Leave comparison', exact: true }).click();
  await page.waitForFunction(() => window.__cgview.scene.panes === 0);
  assert.deepEqual(v.problems, [], v.describeProblems());
});
