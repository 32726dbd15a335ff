// End-to-end test of CGAL's filters in the viewer, against the real server:
// simplify the elephant from the algorithm form, add its output mesh to the
// view (a second scene object, drawn), then "Run on this": hausdorff on that
// output against the original elephant, chosen in the form's reference
// chooser. The chained output becomes a mesh of its own in the list, and the
// per-vertex distance is drawn on it as a colour map, with the metrics table.
// Then a voxel grid chains the same way: grid_surface on voxelize's grid.
// The canvas is kept in build/test-artifacts/e2e-filters-*.png.
//
// Environment: CGVIEW_SERVER (default build/bin/cgview-server),
// CHROMIUM (default /usr/bin/chromium).
import { test } from 'node:test';
import assert from 'node:assert/strict';
import path from 'node:path';
import { artifactsDir as artifacts, hueStats, useViewer, pngPixels, repo } from './harness.mjs';

const elephant = path.join(repo, 'build', 'samples', 'elephant.off');
const TARGET_FACES = 1000;

// The viewer (server, page, problems), open for this file's tests.
const v = useViewer({ tmpPrefix: 'cgview-e2e-filters-', mesh: elephant });

async function waitDone(algorithm) {
  const li = v.page.locator(`#jobs li.job[data-algorithm="${algorithm}"][data-state="done"]`).first();
  await li.waitFor({ timeout: 120000 }).catch(async (e) => {
    const states = await v.page.locator('#jobs li.job').evaluateAll((ls) => ls.map((l) => `${l.dataset.algorithm}:${l.dataset.state}:${l.innerText}`));
    throw new Error(`${algorithm} never showed done: ${e.message}\njobs: ${states.join('\n')}${v.describeProblems()}\n${v.server.log()}`);
  });
  return li;
}

async function selectAlgorithm(name) {
  await v.page.locator('#algorithm-menu').selectOption(name);
  const form = v.page.locator(`form.algorithm-form[data-algorithm="${name}"]`);
  await form.waitFor();
  return form;
}

let simplifyJob = null;

test('simplify from the form: its output mesh is added to the view as a second object', async () => {
  const form = await selectAlgorithm('simplify');
  await form.locator('input[data-param="target_faces"]').fill(String(TARGET_FACES));
  await form.locator('button.run').click();
  const done = await waitDone('simplify');
  simplifyJob = await done.getAttribute('data-job-id');
  const row = done.locator('.artifact-mesh[data-artifact="mesh"]');
  await row.locator('button.add').click();
  await v.page.waitForFunction((id) => window.__cgview.lastExtra?.jobId === id, simplifyJob, { timeout: 30000 });
  const extra = await v.page.evaluate(() => window.__cgview.lastExtra);
  assert.ok(extra.faces <= TARGET_FACES && extra.faces >= 0.9 * TARGET_FACES, `the simplified mesh has about ${TARGET_FACES} faces: ${JSON.stringify(extra)}`);
  assert.equal(await row.locator('button.add').innerText(), 'Added');
  const png = await v.page.locator('#viewport canvas').screenshot({ path: path.join(artifacts, 'e2e-filters-simplified.png') });
  const h = hueStats(await pngPixels(v.page, png));
  assert.ok(h.saturated > 5000, `the meshes are drawn: ${JSON.stringify(h)}`);
  assert.deepEqual(v.problems, [], v.describeProblems());
});

test('"Run on this" chains: hausdorff of the simplified mesh against the elephant, drawn as a colour map', async () => {
  assert.ok(simplifyJob, 'the simplify test ran');
  const meshesBefore = await v.page.locator('#mesh-list li.mesh').count();
  const done = v.page.locator(`#jobs li.job[data-job-id="${simplifyJob}"]`);
  await done.locator('.artifact-mesh[data-artifact="mesh"] button.run-on').click();
  const form = await selectAlgorithm('hausdorff');
  assert.match(await form.locator('.run-target').innerText(), /elephant · simplify 1000/, 'the form runs on the chosen output, named after what it was made from');
  // The reference chooser lists the stored meshes; the elephant is the reference.
  const reference = form.locator('select[data-input="reference"]');
  const options = await reference.locator('option').evaluateAll((os) => os.map((o) => o.value));
  assert.ok(options.includes(v.meshId), `the reference chooser lists the elephant: ${options}`);
  await reference.selectOption(v.meshId);
  await form.locator('button.run').click();

  const li = await waitDone('hausdorff');
  const jobId = await li.getAttribute('data-job-id');
  const job = await (await fetch(`${v.server.url}/api/v1/jobs/${jobId}`)).json();
  assert.equal(job.inputs.reference, v.meshId);
  assert.notEqual(job.inputs.mesh, v.meshId, 'the input is the stored output of simplify');
  // The chained output is a mesh of its own in the list, with the simplified counts.
  await v.page.waitForFunction((n) => document.querySelectorAll('#mesh-list li.mesh').length > n, meshesBefore, { timeout: 15000 });
  const stored = await (await fetch(`${v.server.url}/api/v1/meshes/${job.inputs.mesh}`)).json();
  assert.ok(stored.report.faces <= TARGET_FACES, `the stored input is the simplified mesh: ${JSON.stringify(stored.report)}`);

  // The distance field is drawn on it (one value per vertex), with a legend.
  await v.page
    .waitForFunction((id) => window.__cgview.lastField?.jobId === id, jobId, { timeout: 60000 })
    .catch(async (e) => {
      const error = await v.page.evaluate(() => window.__cgview.lastError);
      throw new Error(`no field drawn (page error: ${error}): ${e.message}${v.describeProblems()}`);
    });
  const shown = await v.page.evaluate(() => window.__cgview.lastField);
  assert.equal(shown.meshId, job.inputs.mesh);
  assert.equal(shown.count, stored.report.vertices, 'one value per vertex of the simplified mesh');
  assert.ok(shown.range[0] >= 0 && shown.range[1] > shown.range[0], `distances: ${shown.range}`);
  const png = await v.page.locator('#viewport canvas').screenshot({ path: path.join(artifacts, 'e2e-filters-hausdorff.png') });
  const h = hueStats(await pngPixels(v.page, png));
  assert.ok(h.distinct >= 2 && h.orange < 0.5, `a colour map, not the plain surface: ${JSON.stringify(h)}`);

  // The metrics table: the symmetric distance, small against the elephant's size.
  const table = li.locator('.artifact-metrics table.metrics');
  await table.waitFor({ timeout: 15000 });
  const text = await table.innerText();
  const m = /hausdorff relative\s+([0-9.e-]+) % of diagonal/.exec(text);
  assert.ok(m, `the table shows the relative distance, in per cent of the diagonal:\n${text}`);
  assert.ok(Number(m[1]) > 0 && Number(m[1]) < 5, `simplified to ${TARGET_FACES} faces stays within 5% of the diagonal: ${m[1]} %`);
  assert.deepEqual(v.problems, [], v.describeProblems());
});

test('"Run on this" on a voxel grid: grid_surface takes the grid of voxelize, and its mesh is drawn', async () => {
  await v.page.locator(`#mesh-list li.mesh[data-mesh-id="${v.meshId}"]`).click();
  let form = await selectAlgorithm('voxelize');
  await form.locator('input[data-param="resolution"]').fill('24');
  await form.locator('button.run').click();
  const vox = await waitDone('voxelize');
  // grid_surface needs a grid: without one the form says so.
  form = await selectAlgorithm('grid_surface');
  await form.locator('button.run').click();
  const error = form.locator('.form-error');
  await error.waitFor({ state: 'visible', timeout: 15000 });
  assert.match(await error.innerText(), /voxel_grid/);

  await vox.locator('.artifact-voxel_grid[data-artifact="grid"] button.run-on').click();
  form = await selectAlgorithm('grid_surface');
  assert.match(await form.locator('.run-target').innerText(), /elephant · voxelize 24/);
  await form.locator('button.run').click();
  const li = await waitDone('grid_surface');
  const jobId = await li.getAttribute('data-job-id');
  const job = await (await fetch(`${v.server.url}/api/v1/jobs/${jobId}`)).json();
  assert.equal(job.inputs.grid.job, await vox.getAttribute('data-job-id'));
  await li.locator('.artifact-mesh[data-artifact="mesh"] button.add').click();
  await v.page.waitForFunction((id) => window.__cgview.lastExtra?.jobId === id, jobId, { timeout: 30000 });
  const extra = await v.page.evaluate(() => window.__cgview.lastExtra);
  assert.ok(extra.faces > 100, `the voxel surface has faces: ${JSON.stringify(extra)}`);
  await v.page.locator('#viewport canvas').screenshot({ path: path.join(artifacts, 'e2e-filters-grid-surface.png') });
  assert.deepEqual(v.problems, [], v.describeProblems());
});
