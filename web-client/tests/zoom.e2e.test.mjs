// End-to-end test of zooming, against the real server and Debian's chromium:
//   CGVIEW_SERVER=build/bin/cgview-server node --test tests/zoom.e2e.test.mjs
//
// A flat square and a wavy one, 1 unit across and then 10,000 units
// across (OFF text made here), are zoomed into with the mouse wheel, 90
// notches, close to the orbit centre on the square, then out 135: in the
// single view and side by side (the Scene panel's two panes), the centre of
// every pane still shows the mesh after each batch of notches, the near
// plane stays in front of the mesh's box and the far one behind it. Planes
// set once when the mesh was framed cut the square away after some twenty
// notches in (the near plane stays where it was) or a few out.
//
// Environment: CGVIEW_SERVER (default build/bin/cgview-server), CHROMIUM.
import assert from 'node:assert/strict';
import fs from 'node:fs';
import path from 'node:path';
import { artifactsDir, pngPixels, settle, test, useViewer } from './harness.mjs';

const v = useViewer({ tmpPrefix: 'cgview-zoom-' });

/** An n × n grid of quads `size` across in the z = 0 plane, centred on the origin; `wave`: one wave along x, a tenth of its size high, through the origin. */
function grid(size, wave, n = 8) {
  const vertices = [];
  for (let j = 0; j <= n; ++j) {
    for (let i = 0; i <= n; ++i) {
      const x = (i / n - 0.5) * size;
      const y = (j / n - 0.5) * size;
      const z = wave ? 0.05 * size * Math.sin((2 * Math.PI * x) / size) : 0;
      vertices.push([x, y, z]);
    }
  }
  const faces = [];
  for (let j = 0; j < n; ++j) {
    for (let i = 0; i < n; ++i) {
      const a = j * (n + 1) + i;
      faces.push([a, a + 1, a + n + 2, a + n + 1]);
    }
  }
  const lo = [0, 1, 2].map((k) => Math.min(...vertices.map((p) => p[k])));
  const hi = [0, 1, 2].map((k) => Math.max(...vertices.map((p) => p[k])));
  const text = `OFF\n${vertices.length} ${faces.length} 0\n${vertices.map((p) => p.join(' ')).join('\n')}\n${faces.map((f) => `4 ${f.join(' ')}`).join('\n')}\n`;
  return { text, lo, hi };
}

async function upload(name, text) {
  const r = await fetch(`${v.server.url}/api/v1/meshes?name=${encodeURIComponent(name)}`, { method: 'POST', body: text });
  assert.equal(r.status, 201, await r.clone().text());
  return (await r.json()).id;
}

const BACKGROUND = [0x1b, 0x1d, 0x22];

/** Share of the pixels within 6 px of (x, y) that are not the background. */
function coverage(img, x, y) {
  let n = 0;
  let hit = 0;
  for (let dy = -6; dy <= 6; ++dy) {
    for (let dx = -6; dx <= 6; ++dx) {
      const i = ((Math.round(y) + dy) * img.width + Math.round(x) + dx) * 4;
      ++n;
      if (Math.abs(img.data[i] - BACKGROUND[0]) + Math.abs(img.data[i + 1] - BACKGROUND[1]) + Math.abs(img.data[i + 2] - BACKGROUND[2]) > 40) ++hit;
    }
  }
  return hit / n;
}

/** The least and greatest depth of the box [lo, hi] seen from `eye` looking along the unit vector `forward` (its corners are the extremes). */
function boxDepths(eye, forward, lo, hi) {
  let nearest = 0;
  let farthest = 0;
  for (let k = 0; k < 3; ++k) {
    const a = (lo[k] - eye[k]) * forward[k];
    const b = (hi[k] - eye[k]) * forward[k];
    nearest += Math.min(a, b);
    farthest += Math.max(a, b);
  }
  return { nearest, farthest };
}

/**
 * Wheels `notches` times over pane `pane` of `panes` (side by side; 1: the
 * single view) in batches; after each batch, the centre of every pane shows
 * the mesh and the planes enclose the box [lo, hi].
 */
async function zoom(label, notches, { panes, lo, hi }) {
  const { page } = v;
  const canvas = await page.locator('#viewport canvas').boundingBox();
  const centres = Array.from({ length: panes }, (_, i) => [((i + 0.5) * canvas.width) / panes, canvas.height / 2]);
  await page.mouse.move(canvas.x + centres[0][0], canvas.y + centres[0][1]);
  const batch = Math.sign(notches) * 15;
  for (let done = 0; Math.abs(done) < Math.abs(notches); done += batch) {
    for (let k = 0; k < Math.abs(batch); ++k) await page.mouse.wheel(0, batch > 0 ? -100 : 100);
    await settle(page, 250);
    const png = await page.locator('#viewport canvas').screenshot();
    const img = await pngPixels(page, png);
    const at = `${label}, ${Math.abs(done + batch)} notches ${batch > 0 ? 'in' : 'out'}`;
    for (const [i, [x, y]] of centres.entries()) {
      const c = coverage(img, x, y);
      if (c < 0.9) fs.writeFileSync(path.join(artifactsDir, `e2e-zoom-failed.png`), png);
      assert.ok(c >= 0.9, `${at}: the centre of pane ${i} shows the mesh (${(c * 100).toFixed(0)}% of its pixels)`);
    }
    const camera = await page.evaluate(() => window.__cgview.camera());
    const { near, far } = await page.evaluate(() => window.__cgview.clipping());
    const { nearest, farthest } = boxDepths(camera.position, camera.direction, lo, hi);
    if (nearest > 0) assert.ok(near < nearest, `${at}: near ${near} is in front of the box (its nearest corner at depth ${nearest})`);
    assert.ok(far > farthest, `${at}: far ${far} is behind the box (its farthest corner at depth ${farthest})`);
    assert.ok(near > 0 && far / near < 1e7, `${at}: near ${near} and far ${far} keep some depth precision`);
  }
}

/** Uploads a flat square and a wavy one `size` across, named after `label`, and shows the square alone. */
async function showSquare(size, label) {
  const { page } = v;
  const flat = grid(size, false);
  const wave = grid(size, true);
  const flatName = `square-${size}-${label}.off`;
  const waveName = `wave-${size}-${label}.off`;
  const flatId = await upload(flatName, flat.text);
  const waveId = await upload(waveName, wave.text);
  await page.locator('#mesh-list li.mesh', { hasText: flatName }).click();
  await page.waitForFunction((id) => window.__cgview.lastLoaded?.id === id, flatId, { timeout: 30000 });
  await settle(page);
  return { flat, wave, flatName, waveName, waveId };
}

// Each size alone and side by side, four tests, so that a ctest of one or
// two of them stays well under a minute (tests/web/CMakeLists.txt).
for (const size of [1, 10000]) {
  test(`a ${size}-unit mesh zoomed into and out of alone is never cut`, async () => {
    const { flat, flatName } = await showSquare(size, 'alone');
    // In to the orbit centre (on the square), then out.
    await zoom(`${flatName} alone`, 90, { panes: 1, lo: flat.lo, hi: flat.hi });
    await zoom(`${flatName} alone`, -135, { panes: 1, lo: flat.lo, hi: flat.hi });
    assert.deepEqual(v.problems, [], v.describeProblems());
  });

  test(`a ${size}-unit mesh zoomed into and out of side by side is never cut`, async () => {
    const { page } = v;
    const { flat, wave, flatName, waveName, waveId } = await showSquare(size, 'pair');
    // Side by side with the wave: both panes, through the one camera.
    await page.getByRole('button', { name: `Add ${waveName} to the scene`, exact: true }).click();
    await page.waitForFunction((id) => window.__cgview.scene.objects[1]?.mesh === id && window.__cgview.scene.objects[1].loaded, waveId, { timeout: 30000 });
    await page.locator('#scene').getByRole('button', { name: 'Side by side', exact: true }).click();
    await page.waitForFunction(() => window.__cgview.scene.panes === 2);
    await settle(page);
    const both = { lo: wave.lo.map((x, k) => Math.min(x, flat.lo[k])), hi: wave.hi.map((x, k) => Math.max(x, flat.hi[k])) };
    await zoom(`${flatName} and ${waveName} side by side`, 90, { panes: 2, ...both });
    await zoom(`${flatName} and ${waveName} side by side`, -135, { panes: 2, ...both });
    await page.getByRole('button', { name: 'Leave comparison', exact: true }).click();
    await page.waitForFunction(() => window.__cgview.scene.panes === 0);
    assert.deepEqual(v.problems, [], v.describeProblems());
  });
}
