// End-to-end test of point clouds in the viewer, against the real server and
// Debian's chromium:
//   CGVIEW_SERVER=build/bin/cgview-server node --test tests/points.e2e.test.mjs
//
// A binary PLY point cloud written by Open3D (Debian's python3-open3d: an
// independent writer) is uploaded through the page's file input: the server
// stores it as a mesh with no faces and streams it as a Draco point cloud,
// which the viewer draws as points, as many as the file has, each in the
// file's colour (its left half red, its right half blue: the canvas shows
// both, red to the left of blue); the Display panel's point size makes the
// points bigger on the canvas. estimate_normals, run from the algorithm form
// on the cloud shown (its input is points), makes a `points` artifact with a
// download link per format the server lists, drawn over the cloud when the
// job ends (hidden and shown again from its row), as many points as the
// cloud, with normals. A green cloud with normals (Open3D's file again) is shaded by
// them: its points facing the camera in the file's full green, those seen
// edge-on darker; the Display panel's "Vertex normals" draws them. The
// canvas is kept in build/test-artifacts/e2e-points-*.png.
//
// Environment: CGVIEW_SERVER (default build/bin/cgview-server), CHROMIUM.
import { after, test } from 'node:test';
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { artifactsDir, doneRow, pngPixels, settle, useViewer, VIEW_BACKGROUND } from './harness.mjs';

/** Points of the cloud: a Fibonacci sphere of radius 1, red where x < 0, blue elsewhere. */
const POINTS = 4000;

const v = useViewer({ tmpPrefix: 'cgview-e2e-points-' });
const tmp = fs.mkdtempSync(path.join(os.tmpdir(), 'cgview-points-'));
after(() => fs.rmSync(tmp, { recursive: true, force: true }));

/**
 * Writes the cloud with Open3D (binary PLY: float x y z, uchar red green
 * blue, and float nx ny nz with `normals`: the sphere's, its points' own
 * directions); red where x < 0 and blue elsewhere, or all `green`. Returns
 * its point count as Open3D reads it back.
 */
function writeCloud(file, { normals = false, green = false } = {}) {
  const script = `
import sys, numpy as np, open3d as o3d
n = ${POINTS}
i = np.arange(n) + 0.5
y = 1 - 2 * i / n
r = np.sqrt(1 - y * y)
phi = i * np.pi * (3 - np.sqrt(5))
p = np.stack([r * np.cos(phi), y, r * np.sin(phi)], axis=1)
c = np.tile([[0.0, 1.0, 0.0]], (n, 1)) if ${green ? 'True' : 'False'} else np.where(p[:, :1] < 0, [[1.0, 0.0, 0.0]], [[0.0, 0.0, 1.0]])
cloud = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(p))
cloud.colors = o3d.utility.Vector3dVector(c)
if ${normals ? 'True' : 'False'}:
    cloud.normals = o3d.utility.Vector3dVector(p)
assert o3d.io.write_point_cloud(sys.argv[1], cloud, write_ascii=False)
print(len(o3d.io.read_point_cloud(sys.argv[1]).points))
`;
  return Number(execFileSync('/usr/bin/python3', ['-c', script, file], { encoding: 'utf8' }).trim());
}

async function canvas(name) {
  await settle(v.page);
  const png = await v.page.locator('#viewport canvas').screenshot();
  fs.writeFileSync(path.join(artifactsDir, `e2e-points-${name}.png`), png);
  return pngPixels(v.page, png);
}

/** The canvas's red and blue pixels (a channel over 150, the others under 90): how many, and their mean x. */
function redAndBlue({ data, width }) {
  const red = { count: 0, x: 0 };
  const blue = { count: 0, x: 0 };
  for (let i = 0; i < data.length; i += 4) {
    const [r, g, b] = [data[i], data[i + 1], data[i + 2]];
    const which = r > 150 && g < 90 && b < 90 ? red : b > 150 && r < 90 && g < 90 ? blue : null;
    if (!which) continue;
    ++which.count;
    which.x += (i / 4) % width;
  }
  for (const c of [red, blue]) c.x = c.count ? c.x / c.count : NaN;
  return { red, blue };
}

/** Pixels that are not the view's background. */
function drawn({ data }) {
  let n = 0;
  for (let i = 0; i < data.length; i += 4) {
    const d = Math.abs(data[i] - VIEW_BACKGROUND[0]) + Math.abs(data[i + 1] - VIEW_BACKGROUND[1]) + Math.abs(data[i + 2] - VIEW_BACKGROUND[2]);
    if (d > 30) ++n;
  }
  return n;
}

/** Sets the Display panel's point size as a drag of its slider does. */
async function setPointSize(size) {
  await v.page.locator('#display-point-size').evaluate((input, value) => {
    input.value = String(value);
    input.dispatchEvent(new Event('input', { bubbles: true }));
    input.dispatchEvent(new Event('change', { bubbles: true }));
  }, size);
  await v.page.waitForFunction((s) => window.__cgview.display?.cloud?.size === s, size, { timeout: 10000 });
}

let cloudId = null;

test('an uploaded PLY point cloud is drawn as its points, in its colours, their size from the Display panel', async () => {
  const { page } = v;
  const file = path.join(tmp, 'sphere_cloud.ply');
  const count = writeCloud(file);
  assert.equal(count, POINTS, 'Open3D reads back the points it wrote');
  await page.setInputFiles('#file-input', file);
  await page
    .waitForFunction(() => window.__cgview.lastLoaded?.points === true, null, { timeout: 60000 })
    .catch((e) => {
      throw new Error(`the cloud was never shown: ${e.message}${v.describeProblems()}`);
    });
  const loaded = await page.evaluate(() => window.__cgview.lastLoaded);
  cloudId = loaded.id;
  assert.equal(loaded.vertices, POINTS, 'as many points streamed as the file has');
  assert.equal(loaded.faces, 0);
  assert.match(await page.locator(`#mesh-list li.mesh[data-mesh-id="${cloudId}"]`).innerText(), new RegExp(`${POINTS} points`));
  await page.waitForFunction(() => window.__cgview.display?.cloud, null, { timeout: 10000 });
  const cloud = await page.evaluate(() => window.__cgview.display.cloud);
  assert.deepEqual({ points: cloud.points, colors: cloud.colors, normals: cloud.normals }, { points: POINTS, colors: true, normals: false });
  assert.ok(await page.locator('#display-point-size').isVisible(), 'the Display panel offers the point size for a cloud');

  await setPointSize(3);
  const small = await canvas('size3');
  const colours = redAndBlue(small);
  assert.ok(colours.red.count > 500 && colours.blue.count > 500, `the file's red and blue are on the canvas: ${JSON.stringify(colours)}`);
  assert.ok(colours.red.x < colours.blue.x, `red (x < 0) is left of blue: ${JSON.stringify(colours)}`);
  // Between the points the background shows: a cloud, not a surface.
  const smallDrawn = drawn(small);

  await setPointSize(9);
  const big = await canvas('size9');
  const bigDrawn = drawn(big);
  assert.ok(bigDrawn > 1.5 * smallDrawn, `points of 9 px cover more of the canvas than of 3 px: ${bigDrawn} vs ${smallDrawn}`);
  assert.equal((await page.evaluate(() => window.__cgview.display.cloud)).size, 9);
  assert.equal(v.problems.length, 0, v.describeProblems());
});

test('estimate_normals run from the form on the cloud shown: its points artifact has its download links and is drawn over the cloud', async (t) => {
  const { page } = v;
  if (!cloudId) return t.skip('the cloud was not uploaded (the first test failed)');
  const algorithms = await (await fetch(`${v.server.url}/api/v1/algorithms`)).json();
  const list = Array.isArray(algorithms) ? algorithms : (algorithms.algorithms ?? []);
  assert.ok(
    list.some((a) => a.name === 'estimate_normals'),
    'the server lists estimate_normals',
  );
  // Its input is points: the mesh shown (the cloud) is taken, as a mesh is by an algorithm on meshes.
  await page.locator('#algorithm-menu').selectOption('estimate_normals');
  const form = page.locator('form.algorithm-form[data-algorithm="estimate_normals"]');
  await form.waitFor();
  const [submitted] = await Promise.all([
    page.waitForResponse((r) => new URL(r.url()).pathname === '/api/v1/jobs' && r.request().method() === 'POST'),
    form.locator('button.run').click(),
  ]);
  assert.equal(submitted.status(), 201, await submitted.text());
  let job = await submitted.json();
  assert.ok(job, 'Run submitted estimate_normals');
  assert.equal(Object.values(job.inputs)[0], cloudId, 'on the cloud shown');
  const li = await doneRow(v, job.id);
  job = await (await fetch(`${v.server.url}/api/v1/jobs/${job.id}`)).json();
  const artifact = job.artifacts.find((a) => a.kind === 'points');
  assert.ok(artifact, `the job made points: ${JSON.stringify(job.artifacts)}`);
  const row = li.locator(`.artifact-points[data-artifact="${artifact.name}"]`);
  const links = await row.locator('a[download]').evaluateAll((as) => as.map((a) => [a.textContent, new URL(a.href).searchParams.get('format')]));
  const formats = artifact.formats?.length ? artifact.formats : ['drc'];
  assert.deepEqual(
    links.map(([text]) => text),
    formats,
    'a link per format the server lists',
  );
  for (const [text, format] of links) assert.equal(format, text);
  for (const f of formats) {
    const r = await fetch(`${v.server.url}/api/v1/jobs/${job.id}/artifacts/${artifact.name}?format=${f}`);
    assert.equal(r.status, 200, `${f} downloads`);
  }

  // A job run here shows its cloud when it ends; Hide and Show again in its row.
  const drawnPoints = async () => {
    await page.waitForFunction(() => window.__cgview.points.length === 1, null, { timeout: 30000 });
    return (await page.evaluate(() => window.__cgview.points))[0];
  };
  let drawn = await drawnPoints();
  await row.locator('.show-points').click();
  await page.waitForFunction(() => window.__cgview.points.length === 0, null, { timeout: 10000 });
  await row.locator('.show-points').click();
  drawn = await drawnPoints();
  assert.equal(drawn.key, `${job.id}/${artifact.name}`);
  assert.equal(drawn.points, POINTS, 'every point of the cloud, with its normal');
  assert.equal(drawn.normals, true);
  assert.equal(drawn.size, 9, "the Display panel's point size");
  await row.locator('.show-points').click();
  await page.waitForFunction(() => window.__cgview.points.length === 0, null, { timeout: 10000 });
  assert.equal(v.problems.length, 0, v.describeProblems());
});

test('a cloud with normals is shaded by them (facing the camera bright, edge-on dark), and the vertex normals overlay draws them', async (t) => {
  const { page } = v;
  if (!cloudId) return t.skip('the cloud was not uploaded (the first test failed)');
  const file = path.join(tmp, 'green_normals.ply');
  assert.equal(writeCloud(file, { normals: true, green: true }), POINTS);
  const before = await page.evaluate(() => window.__cgview.lastLoaded?.id);
  await page.setInputFiles('#file-input', file);
  await page.waitForFunction((id) => window.__cgview.lastLoaded?.points === true && window.__cgview.lastLoaded.id !== id, before, { timeout: 60000 });
  await page.waitForFunction(() => window.__cgview.display?.cloud?.normals === true, null, { timeout: 10000 });
  const shaded = await canvas('normals');
  // The sphere's disc on the canvas: its points' green by distance from the disc's centre, over its radius.
  const { data, width, height } = shaded;
  let [x0, x1, y0, y1] = [width, 0, height, 0];
  for (let y = 0; y < height; ++y) {
    for (let x = 0; x < width; ++x) {
      const i = (y * width + x) * 4;
      if (data[i + 1] - data[i] > 40) [x0, x1, y0, y1] = [Math.min(x0, x), Math.max(x1, x), Math.min(y0, y), Math.max(y1, y)];
    }
  }
  const [cx, cy, radius] = [(x0 + x1) / 2, (y0 + y1) / 2, (x1 - x0) / 2];
  assert.ok(radius > 50, `the cloud fills part of the canvas: ${JSON.stringify({ x0, x1, y0, y1 })}`);
  const ring = (lo, hi) => {
    let [sum, n] = [0, 0];
    for (let y = 0; y < height; ++y) {
      for (let x = 0; x < width; ++x) {
        const i = (y * width + x) * 4;
        const d = Math.hypot(x - cx, y - cy) / radius;
        if (d < lo || d >= hi || data[i + 1] - data[i] <= 40) continue;
        sum += data[i + 1];
        ++n;
      }
    }
    return n ? sum / n : NaN;
  };
  const [centre, rim] = [ring(0, 0.3), ring(0.92, 1.01)];
  assert.ok(centre > 200, `points facing the camera are drawn in the file's full green: ${centre}`);
  assert.ok(rim < 0.75 * centre, `points seen edge-on are darker: ${rim} vs ${centre}`);

  await page.check('#overlay-vertex-normals');
  await page.waitForFunction(() => window.__cgview.display?.overlays.vertexNormals === true);
  const withNormals = await canvas('normals-overlay');
  let changed = 0;
  for (let i = 0; i < data.length; i += 4) {
    if (Math.abs(withNormals.data[i] - data[i]) + Math.abs(withNormals.data[i + 1] - data[i + 1]) + Math.abs(withNormals.data[i + 2] - data[i + 2]) > 60) ++changed;
  }
  assert.ok(changed > 1000, `the normals are drawn over the cloud: ${changed} pixels changed`);
  await page.uncheck('#overlay-vertex-normals');
  assert.equal(v.problems.length, 0, v.describeProblems());
});
