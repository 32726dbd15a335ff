// End-to-end test of a job's results as objects of their own, against the
// real server and Debian's chromium: `npm run test:e2e`, or
//   CGVIEW_SERVER=build/bin/cgview-server CGVIEW_SAMPLES=build/samples node --test tests/results.e2e.test.mjs
//
// The elephant simplified to 1000 faces: "Add to view" lists the result in
// the Scene panel as "elephant · simplify 1000" and draws it beside the
// elephant (their world boxes, and the pixels of each colour on screen, do
// not overlap); "In place" puts it over the elephant (their boxes on screen
// coincide) and "Beside" back; it hides and goes with the panel's
// controls. "Run on this" runs smooth on it: the form says it runs on
// "elephant · simplify 1000", the mesh list gets a mesh of that name (once,
// however often it is run on), and smooth's result is "elephant · simplify
// 1000 · smooth 2". The canvas is kept in build/test-artifacts/e2e-results-*.png.
//
// Environment: CGVIEW_SERVER, CGVIEW_SAMPLES (default build/samples), CHROMIUM.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import fs from 'node:fs';
import path from 'node:path';
import { artifactsDir, isMeshOrange, pngPixels, repo, settle, useViewer } from './harness.mjs';

const samples = process.env.CGVIEW_SAMPLES ?? path.join(repo, 'build', 'samples');
const v = useViewer({ tmpPrefix: 'cgview-results-', mesh: path.join(samples, 'elephant.off') });

const SIMPLIFIED = 'elephant · simplify 1000';
const isBlue = (r, g, b) => b > 60 && b > 1.3 * r && b > 1.05 * g && b - Math.min(r, g) > 0.3 * b; // the scene's first colour, #3f8fe0, lit

async function canvasPixels(name) {
  await settle(v.page);
  const png = await v.page.locator('#viewport canvas').screenshot();
  fs.writeFileSync(path.join(artifactsDir, `e2e-results-${name}.png`), png);
  return pngPixels(v.page, png);
}

/** The box [x0, y0, x1, y1] in pixels of the pixels of a colour, and how many; null when none. */
function pixelBox(img, is) {
  const box = [Infinity, Infinity, -Infinity, -Infinity];
  let n = 0;
  for (let y = 0; y < img.height; ++y) {
    for (let x = 0; x < img.width; ++x) {
      const i = (y * img.width + x) * 4;
      if (!is(img.data[i], img.data[i + 1], img.data[i + 2])) continue;
      ++n;
      box[0] = Math.min(box[0], x);
      box[1] = Math.min(box[1], y);
      box[2] = Math.max(box[2], x);
      box[3] = Math.max(box[3], y);
    }
  }
  return n ? { box, n } : null;
}

/** The share of the smaller of two boxes [x0, y0, x1, y1] that the other covers. */
function overlap(a, b) {
  const w = Math.min(a[2], b[2]) - Math.max(a[0], b[0]);
  const h = Math.min(a[3], b[3]) - Math.max(a[1], b[1]);
  if (w <= 0 || h <= 0) return 0;
  const area = (q) => (q[2] - q[0]) * (q[3] - q[1]);
  return (w * h) / Math.min(area(a), area(b));
}

const sceneObjects = () => v.page.evaluate(() => window.__cgview.scene.objects);
const sceneRow = (name) => v.page.locator('#scene .scene-object', { has: v.page.getByRole('button', { name, exact: true }) });

async function runAlgorithm(name, params) {
  await v.page.getByLabel('Algorithm', { exact: true }).selectOption(name);
  const form = v.page.locator(`form.algorithm-form[data-algorithm="${name}"]`);
  await form.waitFor();
  for (const [param, value] of Object.entries(params)) await form.locator(`[data-param="${param}"]`).fill(String(value));
  const ids = () => v.page.locator(`#jobs li.job[data-algorithm="${name}"]`).evaluateAll((ls) => ls.map((l) => l.dataset.jobId));
  const before = await ids();
  await form.getByRole('button', { name: 'Run', exact: true }).click();
  const handle = await v.page.waitForFunction(
    ([algorithm, old]) => [...document.querySelectorAll(`#jobs li.job[data-algorithm="${algorithm}"]`)].map((l) => l.dataset.jobId).find((id) => !old.includes(id)),
    [name, before],
    { timeout: 30000 },
  );
  const jobId = await handle.jsonValue();
  const li = v.page.locator(`#jobs li.job[data-job-id="${jobId}"]`);
  await v.page
    .locator(`#jobs li.job[data-job-id="${jobId}"][data-state="done"]`)
    .waitFor({ timeout: 120000 })
    .catch(async (e) => {
      throw new Error(`${name} never showed done: ${e.message}: ${await li.innerText()}${v.describeProblems()}`);
    });
  return { li, form, jobId };
}

let simplify = null;

test('"Add to view": the result is listed in the Scene panel by its name and drawn beside its source, or in place over it', async () => {
  const { page } = v;
  simplify = await runAlgorithm('simplify', { target_faces: 1000 });
  const row = simplify.li.locator('.artifact-mesh[data-artifact="mesh"]');
  await row.getByRole('button', { name: 'Add to view' }).click();
  await page.waitForFunction((id) => window.__cgview.lastExtra?.jobId === id, simplify.jobId, { timeout: 30000 });
  await row.getByRole('button', { name: 'Added' }).waitFor();

  // Its own entry in the Scene panel, with its controls.
  await sceneRow(SIMPLIFIED).waitFor();
  assert.equal(await page.locator('#scene .scene-object').count(), 2);
  const result = sceneRow(SIMPLIFIED);
  assert.ok(await result.getByRole('checkbox', { name: `Show ${SIMPLIFIED}` }).isChecked());
  assert.ok(await result.getByRole('button', { name: `Remove ${SIMPLIFIED} from the scene` }).isVisible());
  assert.equal(await result.getByRole('button', { name: 'Beside' }).getAttribute('aria-pressed'), 'true');

  // Beside: framed together, apart in the world and in the picture.
  await page.waitForFunction(() => window.__cgview.scene.objects.every((o) => o.loaded && o.box));
  await settle(page);
  let objects = await sceneObjects();
  assert.equal(objects[1].name, SIMPLIFIED);
  // The world boxes do not overlap: the result (within the elephant's box) moved by more than the box's width.
  const { bbox } = (await (await fetch(`${v.server.url}/api/v1/meshes/${v.meshId}`)).json()).report;
  const gap = objects[1].position[0] - objects[0].position[0];
  assert.ok(gap > bbox.max[0] - bbox.min[0], `moved by ${gap}, more than the width ${bbox.max[0] - bbox.min[0]}`);
  for (const o of objects)
    assert.ok(
      o.box.every((x) => x >= -1.001 && x <= 1.001),
      `${o.name} in view: ${o.box}`,
    );
  let img = await canvasPixels('beside');
  let orange = pixelBox(img, isMeshOrange);
  let blue = pixelBox(img, isBlue);
  assert.ok(orange?.n > 500 && blue?.n > 500, `both drawn: ${orange?.n} orange, ${blue?.n} blue pixels`);
  assert.ok(blue.box[0] > orange.box[2] || orange.box[0] > blue.box[2], `apart in the picture: orange ${orange.box}, blue ${blue.box}`);

  // In place: over the elephant, for comparison.
  await result.getByRole('button', { name: 'In place' }).click();
  await page.waitForFunction(() => {
    const [s, r] = window.__cgview.scene.objects;
    return r.position.every((x, i) => x === s.position[i]);
  });
  await settle(page);
  assert.equal(await sceneRow(SIMPLIFIED).getByRole('button', { name: 'In place' }).getAttribute('aria-pressed'), 'true');
  objects = await sceneObjects();
  assert.ok(overlap(objects[0].box, objects[1].box) > 0.9, `the boxes coincide: ${JSON.stringify(objects.map((o) => o.box))}`);
  img = await canvasPixels('in-place');
  orange = pixelBox(img, isMeshOrange);
  blue = pixelBox(img, isBlue);
  assert.ok(orange && blue && overlap(orange.box, blue.box) > 0.8, `one over the other in the picture: orange ${orange?.box}, blue ${blue?.box}`);

  // Beside again; then hidden, and removed.
  await sceneRow(SIMPLIFIED).getByRole('button', { name: 'Beside' }).click();
  await page.waitForFunction(() => {
    const [s, r] = window.__cgview.scene.objects;
    return r.position[0] > s.position[0];
  });
  await sceneRow(SIMPLIFIED)
    .getByRole('checkbox', { name: `Show ${SIMPLIFIED}` })
    .uncheck();
  await page.waitForFunction(() => window.__cgview.scene.objects[1].visible === false);
  img = await canvasPixels('hidden');
  assert.ok((pixelBox(img, isBlue)?.n ?? 0) < 20, 'no blue left once hidden');
  await sceneRow(SIMPLIFIED)
    .getByRole('button', { name: `Remove ${SIMPLIFIED} from the scene` })
    .click();
  await page.waitForFunction(() => window.__cgview.scene.objects.length === 1);
  await row.getByRole('button', { name: 'Add to view' }).waitFor();
  assert.deepEqual(v.problems, [], v.describeProblems());
});

test('"Run on this" stores the result as "<mesh> · <algorithm> <value>", once, and names what is made from it after it', async () => {
  const { page, server } = v;
  assert.ok(simplify, 'the simplify test ran');
  const runOn = () => simplify.li.locator('.artifact-mesh[data-artifact="mesh"]').getByRole('button', { name: 'Run on this' }).click();
  await runOn();
  await page.getByLabel('Algorithm', { exact: true }).selectOption('smooth');
  const form = page.locator('form.algorithm-form[data-algorithm="smooth"]');
  await form.waitFor();
  assert.equal(await form.locator('.run-target').innerText(), `on ${SIMPLIFIED}`);
  const smooth = await runAlgorithm('smooth', { iterations: 2 });

  // The mesh it ran on is in the list under the result's name.
  const named = page.locator('#mesh-list li.mesh .mesh-name', { hasText: SIMPLIFIED });
  await named.first().waitFor({ timeout: 15000 });
  assert.equal(await named.count(), 1);
  const job = await (await fetch(`${server.url}/api/v1/jobs/${smooth.jobId}`)).json();
  const stored = await (await fetch(`${server.url}/api/v1/meshes/${job.inputs.mesh}`)).json();
  assert.equal(stored.name, SIMPLIFIED);
  assert.ok(stored.report.faces <= 1000, `the simplified mesh: ${JSON.stringify(stored.report)}`);

  // Its own result is named after it.
  await smooth.li.locator('.artifact-mesh[data-artifact="mesh"]').getByRole('button', { name: 'Add to view' }).click();
  await page.waitForFunction((id) => window.__cgview.lastExtra?.jobId === id, smooth.jobId, { timeout: 30000 });
  await sceneRow(`${SIMPLIFIED} · smooth 2`).waitFor();
  const objects = await sceneObjects();
  assert.deepEqual(
    objects.map((o) => o.name),
    [SIMPLIFIED, `${SIMPLIFIED} · smooth 2`],
  );

  // Run on again: the same content is not stored twice.
  await runOn();
  await runAlgorithm('smooth', { iterations: 3 });
  assert.equal(await named.count(), 1, 'one mesh of that name');
  const meshes = (await (await fetch(`${server.url}/api/v1/meshes`)).json()).meshes;
  assert.equal(meshes.filter((m) => m.name === SIMPLIFIED).length, 1, `stored once: ${meshes.map((m) => m.name)}`);
  assert.deepEqual(v.problems, [], v.describeProblems());
});
