// End-to-end test of skeletons in the viewer, against the real server: the
// paper's skeleton from projections and CGAL's MCF skeleton of the elephant,
// run from the algorithm form, drawn over the mesh at once in two colours
// (the paper's Figure 5), compared in a table and side by side in two
// synchronized panes, then one hidden again; then a skeleton file (.cg,
// written here from MCF's skeleton, moved off it) loaded with "Load skeleton
// file…" and drawn, and a malformed one refused naming its line. The canvas
// is kept in build/test-artifacts/e2e-skeletons-*.png.
//
// Environment: CGVIEW_SERVER (default build/bin/cgview-server),
// CHROMIUM (default /usr/bin/chromium).
import { test } from 'node:test';
import assert from 'node:assert/strict';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { artifactsDir as artifacts, useViewer, pngPixels, repo } from './harness.mjs';

const elephant = path.join(repo, 'build', 'samples', 'elephant.off');
const v = useViewer({ tmpPrefix: 'cgview-e2e-skeletons-', mesh: elephant });

async function run(algorithm) {
  await v.page.locator('#algorithm-menu').selectOption(algorithm);
  const form = v.page.locator(`form.algorithm-form[data-algorithm="${algorithm}"]`);
  await form.waitFor();
  await form.locator('button.run').click();
  const li = v.page.locator(`#jobs li.job[data-algorithm="${algorithm}"][data-state="done"]`).first();
  await li.waitFor({ timeout: 180000 }).catch((e) => {
    throw new Error(`${algorithm} never showed done: ${e.message}${v.describeProblems()}\n${v.server.log()}`);
  });
  return li;
}

// Pixels of the canvas within `tolerance` of an sRGB colour.
function countColour(pixels, hex, tolerance = 40) {
  const n = parseInt(hex.slice(1), 16);
  const [r, g, b] = [(n >> 16) & 255, (n >> 8) & 255, n & 255];
  let count = 0;
  for (let i = 0; i < pixels.data.length; i += 4) {
    if (Math.abs(pixels.data[i] - r) + Math.abs(pixels.data[i + 1] - g) + Math.abs(pixels.data[i + 2] - b) < tolerance) ++count;
  }
  return count;
}

test('two skeletons of the elephant drawn at once, each in its colour, then one hidden', async () => {
  const projection = await run('skeleton_projection');
  const mcf = await run('skeleton_mcf');
  for (const li of [projection, mcf]) await li.locator('.artifact-skeleton[data-artifact="skeleton"] button.show-skeleton').click();
  await v.page.waitForFunction(() => window.__cgview.skeletons.length === 2, null, { timeout: 30000 });
  const drawn = await v.page.evaluate(() => window.__cgview.skeletons);
  assert.notEqual(drawn[0].color, drawn[1].color, 'each skeleton has its own colour');
  for (const s of drawn) assert.ok(s.nodes > 20 && s.edges >= s.nodes - 5, `a skeleton of the elephant: ${JSON.stringify(s)}`);
  // The job list shows the colours; both metrics tables list the same measures.
  for (const li of [projection, mcf]) {
    await li.locator('.artifact-skeleton .swatch').waitFor();
    assert.match(await li.locator('.artifact-metrics').innerText(), /endpoints[\s\S]*inside fraction/);
  }
  // The comparison table: a column per skeleton, its job's measures, and the
  // distance the server's skeleton_distance measured.
  const table = v.page.locator('#skeletons table.skeleton-table');
  await table.waitFor();
  assert.equal(await table.locator('tr').first().locator('th[data-skeleton]').count(), 2);
  for (const [i, li] of [projection, mcf].entries()) {
    const jobId = await li.getAttribute('data-job-id');
    const metrics = await (await fetch(`${v.server.url}/api/v1/jobs/${jobId}/artifacts/metrics?format=json`)).json();
    assert.equal(await table.locator('tr[data-metric="endpoints"] td').nth(i).innerText(), String(metrics.endpoints));
    assert.match(await table.locator('tr[data-metric="length"] td').nth(i).innerText(), /^[0-9.]+ mesh units$/, 'a length, with its unit');
  }
  const distanceJob = v.page.locator('#jobs li.job[data-algorithm="skeleton_distance"][data-state="done"]').first();
  await distanceJob.waitFor({ timeout: 120000 }).catch(async (e) => {
    const states = await v.page.locator('#jobs li.job').evaluateAll((ls) => ls.map((l) => `${l.dataset.algorithm}:${l.dataset.state}`));
    throw new Error(`skeleton_distance never showed done: ${e.message}\njobs: ${states.join(' ')}${v.describeProblems()}\n${v.server.log()}`);
  });
  const distanceCell = table.locator('tr[data-metric="distance"] td').nth(1);
  // The table is drawn anew on each change: ask the page, not a handle.
  await v.page
    .waitForFunction(() => /^[0-9.e-]+ \/ [0-9.e-]+ mesh units$/.test(document.querySelectorAll('#skeletons tr[data-metric="distance"] td')[1]?.textContent ?? ''), null, {
      timeout: 60000,
    })
    .catch(async (e) => {
      throw new Error(`the distance cell reads '${await distanceCell.innerText()}': ${e.message}${v.describeProblems()}`);
    });
  const distanceId = await distanceJob.getAttribute('data-job-id');
  const d = await (await fetch(`${v.server.url}/api/v1/jobs/${distanceId}/artifacts/metrics?format=json`)).json();
  // Both distances are lengths: the unit once, after them.
  const [h, mean] = (await distanceCell.innerText())
    .replace(/ mesh units$/, '')
    .split(' / ')
    .map(Number);
  assert.ok(Math.abs(h - d.hausdorff) <= 1e-3 * d.hausdorff && Math.abs(mean - d.mean) <= 1e-3 * d.mean, `${h} / ${mean} against ${JSON.stringify(d)}`);
  assert.ok(d.hausdorff > 0 && d.hausdorff < 0.5, `two skeletons of one elephant are close: ${JSON.stringify(d)}`);

  const png = await v.page.locator('#viewport canvas').screenshot({ path: path.join(artifacts, 'e2e-skeletons-both.png') });
  const pixels = await pngPixels(v.page, png);
  for (const s of drawn) assert.ok(countColour(pixels, s.color) > 200, `skeleton ${s.key} is drawn in ${s.color}`);

  // Side by side: a pane each, through the one camera; each pane shows its own skeleton only.
  await v.page.locator('#skeletons button.side-by-side').click();
  await v.page.waitForFunction(() => window.__cgview.lastCompare?.panes.length === 2, null, { timeout: 30000 });
  const panes = await v.page.evaluate(() => window.__cgview.lastCompare.panes.map((p) => `${p.jobId}/${p.artifact}`));
  assert.deepEqual(
    panes,
    drawn.map((s) => s.key),
  );
  const sideBySide = await pngPixels(v.page, await v.page.locator('#viewport canvas').screenshot({ path: path.join(artifacts, 'e2e-skeletons-side.png') }));
  const half = (pixels, right) => {
    const w = pixels.width,
      h = pixels.height,
      out = new Uint8Array((w >> 1) * h * 4);
    for (let y = 0; y < h; ++y) out.set(pixels.data.subarray((y * w + (right ? w - (w >> 1) : 0)) * 4, (y * w + (right ? w : w >> 1)) * 4), y * (w >> 1) * 4);
    return { width: w >> 1, height: h, data: out };
  };
  for (const [i, s] of drawn.entries()) {
    const own = half(sideBySide, i === 1),
      other = half(sideBySide, i === 0);
    assert.ok(countColour(own, s.color) > 100, `pane ${i} shows ${s.color}`);
    assert.ok(countColour(other, s.color) < 20, `only pane ${i} shows ${s.color}`);
  }
  await v.page.locator('#leave-compare').click();
  await v.page.waitForFunction(() => window.__cgview.lastCompare === null && !document.querySelector('.compare-view'), null, { timeout: 10000 });

  await mcf.locator('.artifact-skeleton button.show-skeleton').click();
  await v.page.waitForFunction(() => window.__cgview.skeletons.length === 1, null, { timeout: 30000 });
  const png2 = await v.page.locator('#viewport canvas').screenshot({ path: path.join(artifacts, 'e2e-skeletons-one.png') });
  const left = await v.page.evaluate(() => window.__cgview.skeletons[0]);
  const pixels2 = await pngPixels(v.page, png2);
  const hidden = drawn.find((s) => s.key !== left.key);
  assert.ok(countColour(pixels2, hidden.color) < 20, `the hidden skeleton is gone: ${countColour(pixels2, hidden.color)} pixels of ${hidden.color}`);
  assert.ok(countColour(pixels2, left.color) > 200, 'the other stays');
  assert.deepEqual(v.problems, [], v.describeProblems());
});

test('a skeleton file chosen with "Load skeleton file…" is attached to the mesh and drawn', async () => {
  // The file: MCF's skeleton of the elephant from the first test, as the .cg
  // text of the mesh-contraction tools (1-based), written here, its nodes
  // moved a little so that it is not the skeleton the server has already.
  const { jobs } = await (await fetch(`${v.server.url}/api/v1/jobs`)).json();
  const mcfJob = jobs.find((j) => j.algorithm === 'skeleton_mcf' && j.state === 'done');
  assert.ok(mcfJob, 'the first test made an MCF skeleton');
  const source = await (await fetch(`${v.server.url}/api/v1/jobs/${mcfJob.id}/artifacts/skeleton?format=json`)).json();
  const nodes = source.nodes.map(([x, y, z]) => [x * 0.999, y * 0.999, z * 0.999]);
  const cg = [`# D:3 NV:${nodes.length} NE:${source.edges.length}`, ...nodes.map((p) => `v ${p.join(' ')}`), ...source.edges.map(([a, b]) => `e ${a + 1} ${b + 1}`)];
  const dir = fs.mkdtempSync(path.join(os.tmpdir(), 'cgview-e2e-skeleton-file-'));
  const file = path.join(dir, 'elephant_tool.cg');
  fs.writeFileSync(file, cg.join('\n') + '\n');
  const before = await v.page.evaluate(() => window.__cgview.skeletons.map((s) => s.key));

  await v.page.locator('#skeletons button.load-skeleton').waitFor();
  await v.page.setInputFiles('#skeleton-file-input', file);
  const li = v.page.locator('#jobs li.job[data-algorithm="import"][data-state="done"]').first();
  await li.waitFor({ timeout: 60000 }).catch((e) => {
    throw new Error(`the import of the skeleton file never showed done: ${e.message}${v.describeProblems()}\n${v.server.log()}`);
  });
  const jobId = await li.getAttribute('data-job-id');
  await v.page.waitForFunction((n) => window.__cgview.skeletons.length === n, before.length + 1, { timeout: 30000 });
  const drawn = (await v.page.evaluate(() => window.__cgview.skeletons)).find((s) => !before.includes(s.key));
  assert.equal(drawn.key, `${jobId}/skeleton`);
  assert.equal(drawn.nodes, nodes.length, 'every node of the file is drawn');
  assert.equal(drawn.edges, source.edges.length, 'every edge of the file is drawn');
  // It was uploaded as the file (POST /data) for the mesh shown: the import job names the file and the mesh.
  const job = await (await fetch(`${v.server.url}/api/v1/jobs/${jobId}`)).json();
  assert.equal(job.params.file, 'elephant_tool.cg');
  assert.equal(job.inputs.mesh, v.meshId);
  // Its column in the comparison table, with the measures of its job.
  const table = v.page.locator('#skeletons table.skeleton-table');
  await table.locator(`th[data-skeleton="${jobId}/skeleton"]`).waitFor({ timeout: 30000 });
  const png = await v.page.locator('#viewport canvas').screenshot({ path: path.join(artifacts, 'e2e-skeletons-file.png') });
  assert.ok(countColour(await pngPixels(v.page, png), drawn.color) > 200, `the file's skeleton is drawn in ${drawn.color}`);

  // A malformed file: refused, the page says which line, nothing drawn.
  const bad = path.join(dir, 'broken.cg');
  fs.writeFileSync(bad, '# D:3 NV:2 NE:1\nv 0 0 0\nv 1 0 0\ne 1 7\n');
  const count = before.length + 1;
  await v.page.setInputFiles('#skeleton-file-input', bad);
  const message = v.page.locator('#messages .message.error', { hasText: 'broken.cg' });
  await message.waitFor({ timeout: 30000 });
  assert.match(await message.innerText(), /line 4/);
  assert.equal(await v.page.evaluate(() => window.__cgview.skeletons.length), count);
  // The refusal (the 400 and the browser's console line about it) is the one error of this test.
  const problems = v.problems.splice(0);
  assert.ok(problems.length > 0 && problems.every((p) => /400.*\/api\/v1\/data/.test(p)), problems.join('\n'));
  fs.rmSync(dir, { recursive: true, force: true });
});
