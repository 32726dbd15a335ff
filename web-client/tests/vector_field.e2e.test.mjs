// End-to-end test of vector fields in the viewer, against the real server and
// Debian's chromium:
//   CGVIEW_SERVER=build/bin/cgview-server node --test tests/vector_field.e2e.test.mjs
//
// principal_directions is run on the elephant from the algorithm form; "Show"
// on its max_direction draws a line segment through every vertex over the
// mesh (one LineSegments of two points a vertex with a value, the values
// mapped to the streamed mesh through its stored order): the canvas changes
// where the mesh is and nowhere far from it, and the row says how many
// vertices have no value. The length slider makes the lines longer; "Hide"
// takes the lines away and the picture is the one before; with "Z up" the
// lines turn with the mesh; a view link keeps the field drawn across a reload. A fit too small for most vertices (one
// ring, degree 3) leaves them NaN: those are skipped, and the row says how
// many. The canvas is kept in
// build/test-artifacts/e2e-vector-field-*.png.
//
// Environment: CGVIEW_SERVER (default build/bin/cgview-server),
// CGVIEW_SAMPLES (default build/samples), CHROMIUM.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import fs from 'node:fs';
import path from 'node:path';
import { artifactsDir, doneRow, pngPixels, repo, settle, submitJob, useViewer } from './harness.mjs';

const samples = process.env.CGVIEW_SAMPLES ?? path.join(repo, 'build', 'samples');
const elephant = path.join(samples, 'elephant.off');
const ELEPHANT_VERTICES = 2775;

const v = useViewer({ tmpPrefix: 'cgview-e2e-vectors-', mesh: elephant });

let jobId = null;
let key = null;
/** The canvas before the field is drawn. */
let plain = null;

async function canvas(name) {
  await settle(v.page);
  const png = await v.page.locator('#viewport canvas').screenshot();
  fs.writeFileSync(path.join(artifactsDir, `e2e-vector-field-${name}.png`), png);
  return pngPixels(v.page, png);
}

/** Pixels that differ by more than `tolerance` (summed over r, g, b), inside the box [x0, x1) × [y0, y1) in pixels and outside it. */
function changed(a, b, box, tolerance = 30) {
  let inside = 0;
  let outside = 0;
  for (let y = 0; y < a.height; ++y) {
    for (let x = 0; x < a.width; ++x) {
      const i = (y * a.width + x) * 4;
      const d = Math.abs(a.data[i] - b.data[i]) + Math.abs(a.data[i + 1] - b.data[i + 1]) + Math.abs(a.data[i + 2] - b.data[i + 2]);
      if (d <= tolerance) continue;
      if (x >= box[0] && x < box[1] && y >= box[2] && y < box[3]) ++inside;
      else ++outside;
    }
  }
  return { inside, outside };
}

/**
 * Pixels of the background in `bare` (the viewer's #1b1d22) that differ in
 * `drawn` by more than a dark line over it does: lines drawn off the mesh.
 * Those at the outline overhang it by a few pixels (about 300 on the
 * elephant); lines not where the mesh is (not turned with it) are thousands.
 */
function offMesh(bare, drawn, tolerance = 15) {
  let n = 0;
  const bg = [0x1b, 0x1d, 0x22];
  for (let i = 0; i < bare.data.length; i += 4) {
    if (Math.abs(bare.data[i] - bg[0]) + Math.abs(bare.data[i + 1] - bg[1]) + Math.abs(bare.data[i + 2] - bg[2]) > 6) continue;
    if (Math.abs(bare.data[i] - drawn.data[i]) + Math.abs(bare.data[i + 1] - drawn.data[i + 1]) + Math.abs(bare.data[i + 2] - drawn.data[i + 2]) > tolerance) ++n;
  }
  return n;
}

/** The shown mesh's box on the canvas in pixels (the test hooks' box is in normalized device coordinates), grown by `margin` pixels. */
async function meshBox(img, margin) {
  const box = await v.page.evaluate(() => window.__cgview.scene.objects[0]?.box ?? null);
  assert.ok(box, 'the mesh has a box on the canvas');
  const [x0, y0, x1, y1] = box;
  const px = (x) => ((x + 1) / 2) * img.width;
  const py = (y) => ((1 - y) / 2) * img.height;
  return [px(Math.min(x0, x1)) - margin, px(Math.max(x0, x1)) + margin, py(Math.max(y0, y1)) - margin, py(Math.min(y0, y1)) + margin];
}

/** The mean length of an OFF file's triangles' edges. */
function meanEdge(off) {
  const words = off.split(/\s+/).filter(Boolean);
  const [n, m] = [Number(words[1]), Number(words[2])];
  const p = (i) => words.slice(4 + 3 * i, 7 + 3 * i).map(Number);
  let sum = 0;
  let count = 0;
  for (let f = 0, at = 4 + 3 * n; f < m; ++f, at += Number(words[at]) + 1) {
    const ids = words.slice(at + 1, at + 1 + Number(words[at])).map(Number);
    ids.forEach((a, k) => {
      const [x, y] = [p(a), p(ids[(k + 1) % ids.length])];
      sum += Math.hypot(x[0] - y[0], x[1] - y[1], x[2] - y[2]);
      ++count;
    });
  }
  return sum / count;
}

/** The vector fields drawn, as the test hooks say once a frame has shown them. */
const drawn = () => v.page.evaluate(() => window.__cgview.vectors);

function row() {
  return v.page.locator(`#jobs li.job[data-job-id="${jobId}"] .artifact-vector_field[data-artifact="max_direction"]`);
}

test('principal_directions from the form: its two direction fields are listed with Show', async () => {
  const { page } = v;
  await page.locator('#algorithm-menu').selectOption('principal_directions');
  const form = page.locator('form.algorithm-form[data-algorithm="principal_directions"]');
  await form.waitFor();
  await form.locator('button.run').click();
  const li = page.locator('#jobs li.job[data-algorithm="principal_directions"][data-state="done"]').first();
  await li.waitFor({ timeout: 120000 }).catch((e) => {
    throw new Error(`principal_directions never showed done: ${e.message}${v.describeProblems()}\n${v.server.log()}`);
  });
  jobId = await li.getAttribute('data-job-id');
  key = `${jobId}/max_direction`;
  const job = await (await fetch(`${v.server.url}/api/v1/jobs/${jobId}`)).json();
  const entry = job.artifacts.find((a) => a.name === 'max_direction');
  assert.equal(entry.kind, 'vector_field');
  assert.equal(entry.location, 'vertex');
  assert.equal(entry.hint, 'direction');
  for (const name of ['max_direction', 'min_direction']) {
    assert.equal(await li.locator(`.artifact-vector_field[data-artifact="${name}"] button.show-vectors`).innerText(), 'Show', `${name} has Show`);
  }
  // The job's scalar field (max_curvature) is shown by itself, as for any job run here: the picture to draw over.
  await page.waitForFunction((id) => window.__cgview.lastField?.jobId === id, jobId, { timeout: 60000 });
  plain = await canvas('before');
  assert.deepEqual(v.problems, [], v.describeProblems());
});

test('"Show" draws a segment through every vertex with a value, over the mesh', async () => {
  assert.ok(jobId, 'the job ran');
  const { page } = v;
  // What the server says: vertices whose vector is NaN have no value.
  const f32 = new Float32Array(await (await fetch(`${v.server.url}/api/v1/jobs/${jobId}/artifacts/max_direction?format=f32`)).arrayBuffer());
  assert.equal(f32.length, 3 * ELEPHANT_VERTICES, 'x, y, z per vertex');
  let nan = 0;
  for (let i = 0; i < f32.length; i += 3) if (![f32[i], f32[i + 1], f32[i + 2]].every(Number.isFinite)) ++nan;

  await row().getByRole('button', { name: 'Show' }).click();
  await page
    .waitForFunction((k) => window.__cgview.vectors.some((d) => d.key === k), key, { timeout: 60000 })
    .catch(async (e) => {
      throw new Error(`no vectors drawn (page error: ${await page.evaluate(() => window.__cgview.lastError)}): ${e.message}${v.describeProblems()}`);
    });
  const [d] = await drawn();
  assert.equal(d.type, 'LineSegments');
  assert.equal(d.location, 'vertex');
  assert.equal(d.hint, 'direction');
  assert.equal(d.missing, nan, 'the vectors without a value are those the server has as NaN');
  assert.equal(d.points, 2 * (ELEPHANT_VERTICES - nan), 'two points a vertex with a value');
  // A fraction of the mean edge length: neighbours' segments do not run into one another.
  const edge = meanEdge(fs.readFileSync(elephant, 'utf8'));
  assert.ok(d.length > 0.25 * edge && d.length < 1.5 * edge, `each segment is about an edge long: ${d.length}, mean edge ${edge}`);
  await row().locator('.vector-missing').waitFor();
  const note = await row().locator('.vector-missing').innerText();
  assert.match(note, nan ? new RegExp(`^${nan} of ${ELEPHANT_VERTICES} vertices without a value`) : new RegExp(`^all ${ELEPHANT_VERTICES} vertices have a value`));
  assert.equal(await row().locator('button.show-vectors').innerText(), 'Hide');

  const lines = await canvas('shown');
  const box = await meshBox(lines, 0);
  const near = await meshBox(lines, 20);
  const onMesh = changed(plain, lines, box);
  const aroundMesh = changed(plain, lines, near);
  assert.ok(onMesh.inside > 2000, `the lines change the picture where the mesh is: ${JSON.stringify(onMesh)}`);
  assert.ok(aroundMesh.outside < 50, `and nowhere far from it: ${JSON.stringify(aroundMesh)}`);
  const off = offMesh(plain, lines);
  assert.ok(off < 1000, `only where they overhang the mesh's outline are they over the background: ${off} pixels`);
  assert.deepEqual(v.problems, [], v.describeProblems());
});

/** Moves max_direction's length slider to `log2` (of the scale), as a drag does. */
function length(log2) {
  return row()
    .getByRole('slider', { name: 'Length of max_direction' })
    .evaluate((input, value) => {
      input.value = String(value);
      input.dispatchEvent(new Event('input', { bubbles: true }));
    }, log2);
}

test('the length slider makes the lines longer', async () => {
  assert.ok(key, 'the field is drawn');
  const { page } = v;
  const before = await canvas('length-1');
  const [d1] = await drawn();
  const frames = await page.evaluate(() => window.__cgview.frames);
  await length(2);
  await page.waitForFunction((n) => window.__cgview.frames > n && window.__cgview.vectors[0]?.scale === 4, frames, { timeout: 10000 });
  const [d4] = await drawn();
  assert.ok(Math.abs(d4.length - 4 * d1.length) < 1e-9 * d1.length + 1e-12, `four times as long: ${d1.length} → ${d4.length}`);
  assert.equal(d4.points, d1.points, 'the same segments');
  assert.equal(await row().locator('.vector-length-value').innerText(), '4×');
  await row().screenshot({ path: path.join(artifactsDir, 'e2e-vector-field-row.png') });
  const longer = await canvas('length-4');
  const box = await meshBox(longer, 0);
  assert.ok(changed(before, longer, box).inside > 1000, 'longer lines change the picture');
  await length(0); // as they were, for the tests below
  await page.waitForFunction(() => window.__cgview.vectors[0]?.scale === 1, null, { timeout: 10000 });
  assert.deepEqual(v.problems, [], v.describeProblems());
});

test('"Hide" takes the lines away: the picture is the one before them', async () => {
  assert.ok(key, 'the field is drawn');
  const { page } = v;
  await row().getByRole('button', { name: 'Hide' }).click();
  await page.waitForFunction(() => window.__cgview.vectors.length === 0, null, { timeout: 10000 });
  await row().getByRole('button', { name: 'Show' }).waitFor();
  const hidden = await canvas('hidden');
  const box = await meshBox(hidden, 20);
  const left = changed(plain, hidden, box);
  assert.ok(left.inside + left.outside < 20, `nothing of the lines is left: ${JSON.stringify(left)}`);
  assert.deepEqual(v.problems, [], v.describeProblems());
});

test('"Z up": the lines turn with the mesh', async () => {
  assert.ok(key, 'the job ran');
  const { page } = v;
  const up = async (axis) => {
    await page.getByLabel('Up axis').selectOption(axis);
    await page.waitForFunction((a) => window.__cgview.display?.up === a, axis, { timeout: 10000 });
  };
  await row().getByRole('button', { name: 'Show' }).click();
  await page.waitForFunction((k) => window.__cgview.vectors.some((d) => d.key === k), key, { timeout: 60000 });
  await up('z');
  const turned = await canvas('z-up');
  await row().getByRole('button', { name: 'Hide' }).click();
  await page.waitForFunction(() => window.__cgview.vectors.length === 0, null, { timeout: 10000 });
  const bare = await canvas('z-up-hidden');
  const lines = changed(bare, turned, await meshBox(bare, 20));
  assert.ok(lines.inside > 2000, `the lines are drawn on the turned mesh: ${JSON.stringify(lines)}`);
  assert.ok(lines.outside < 50, `and nowhere far from it: ${JSON.stringify(lines)}`);
  const off = offMesh(bare, turned);
  assert.ok(off < 1000, `only where they overhang the turned mesh's outline are they over the background: ${off} pixels`);
  await up('y');
  assert.deepEqual(v.problems, [], v.describeProblems());
});

test('a view link keeps the field drawn: a reload draws it again; hidden, the link no longer has it', async () => {
  assert.ok(key, 'the job ran');
  const { page } = v;
  const inLink = (k) => new URLSearchParams(location.hash.slice(1)).getAll('show').includes(k);
  await row().getByRole('button', { name: 'Show' }).click();
  await page.waitForFunction(inLink, key, { timeout: 15000 });
  await page.reload();
  await page.waitForFunction(() => window.__cgview?.viewRestored != null, null, { timeout: 60000 });
  const restored = await page.evaluate(() => window.__cgview.viewRestored);
  assert.ok(!restored.error, `restoring failed: ${restored.error}`);
  await page.waitForFunction((k) => window.__cgview.vectors.some((d) => d.key === k), key, { timeout: 60000 });
  const [d] = await drawn();
  assert.equal(d.points, 2 * (ELEPHANT_VERTICES - d.missing));
  await canvas('reloaded');
  await row().getByRole('button', { name: 'Hide' }).click();
  await page.waitForFunction((k) => !new URLSearchParams(location.hash.slice(1)).getAll('show').includes(k), key, { timeout: 15000 });
  assert.deepEqual(v.problems, [], v.describeProblems());
});

test('vectors without a value (NaN) are not drawn, and the row says how many', async () => {
  const { page } = v;
  // One ring is too few points for a cubic at most vertices: they get NaN.
  const id = await submitJob(v, 'principal_directions', { mesh: v.meshId }, { rings: 1, degree: 3 });
  const li = await doneRow(v, id);
  const f32 = new Float32Array(await (await fetch(`${v.server.url}/api/v1/jobs/${id}/artifacts/max_direction?format=f32`)).arrayBuffer());
  let nan = 0;
  for (let i = 0; i < f32.length; i += 3) if (![f32[i], f32[i + 1], f32[i + 2]].every(Number.isFinite)) ++nan;
  assert.ok(nan > 0 && nan < ELEPHANT_VERTICES, `some vertices have no value, not all: ${nan}`);
  const r = li.locator('.artifact-vector_field[data-artifact="max_direction"]');
  await r.getByRole('button', { name: 'Show' }).click();
  const k = `${id}/max_direction`;
  await page.waitForFunction((k) => window.__cgview.vectors.some((d) => d.key === k), k, { timeout: 60000 });
  const d = (await drawn()).find((x) => x.key === k);
  assert.equal(d.missing, nan);
  assert.equal(d.points, 2 * (ELEPHANT_VERTICES - nan), 'only the vectors with a value are drawn');
  assert.equal(await r.locator('.vector-missing').innerText(), `${nan} of ${ELEPHANT_VERTICES} vertices without a value (not drawn)`);
  await r.getByRole('button', { name: 'Hide' }).click();
  await page.waitForFunction(() => window.__cgview.vectors.length === 0, null, { timeout: 10000 });
  // Hidden, the row still says it.
  assert.match(await r.locator('.vector-missing').innerText(), new RegExp(`^${nan} of`));
  assert.deepEqual(v.problems, [], v.describeProblems());
});
