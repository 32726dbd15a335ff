// End-to-end test of a closed mesh whose faces all face inward, against the
// real server and Debian's chromium:
//   CGVIEW_SERVER=build/bin/cgview-server CGVIEW_SAMPLES=build/samples node --test tests/inward.e2e.test.mjs
//
// Two boxes made here, the same but for the order of each triangle's
// vertices: one facing outward (a positive volume), one facing inward (a
// negative volume). The report of the inward one marks "faces inward" as a
// defect and lists the server's warning about it; the outward one's marks
// it as fine and warns of nothing. The Shape Diameter Function run on the
// inward box through the algorithm form is done, and its job says it ran on
// the mesh turned outward.
//
// Environment: CGVIEW_SERVER, CHROMIUM.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { useViewer } from './harness.mjs';

const v = useViewer({ tmpPrefix: 'cgview-inward-' });

// A box 2 × 1 × 1 about the origin; each triangle's normal (by the right
// hand, b - a × c - a) points out of it.
const VERTICES = [
  [-1, -0.5, -0.5],
  [1, -0.5, -0.5],
  [1, 0.5, -0.5],
  [-1, 0.5, -0.5],
  [-1, -0.5, 0.5],
  [1, -0.5, 0.5],
  [1, 0.5, 0.5],
  [-1, 0.5, 0.5],
];
const OUTWARD = [
  [0, 2, 1],
  [0, 3, 2], // z = -0.5, facing -z
  [4, 5, 6],
  [4, 6, 7], // z = +0.5, facing +z
  [0, 1, 5],
  [0, 5, 4], // y = -0.5, facing -y
  [3, 7, 6],
  [3, 6, 2], // y = +0.5, facing +y
  [0, 4, 7],
  [0, 7, 3], // x = -1, facing -x
  [1, 2, 6],
  [1, 6, 5], // x = +1, facing +x
];
const INWARD = OUTWARD.map(([a, b, c]) => [a, c, b]);

/** The signed volume: the sum over the faces of a · (b × c) / 6. */
function signedVolume(faces) {
  let sum = 0;
  for (const [i, j, k] of faces) {
    const [a, b, c] = [VERTICES[i], VERTICES[j], VERTICES[k]];
    const cross = [b[1] * c[2] - b[2] * c[1], b[2] * c[0] - b[0] * c[2], b[0] * c[1] - b[1] * c[0]];
    sum += a[0] * cross[0] + a[1] * cross[1] + a[2] * cross[2];
  }
  return sum / 6;
}

const off = (faces) => ['OFF', `${VERTICES.length} ${faces.length} 0`, ...VERTICES.map((p) => p.join(' ')), ...faces.map((f) => `3 ${f.join(' ')}`), ''].join('\n');

const INWARD_WARNING = 'faces all face inward';
let inwardId = null;
let outwardId = null;

async function upload(name, body) {
  const r = await fetch(`${v.server.url}/api/v1/meshes?name=${encodeURIComponent(name)}`, { method: 'POST', body });
  assert.equal(r.status, 201, await r.clone().text());
  return r.json();
}

/** Shows the mesh through the list, as a user would, and waits until it is drawn and its report is shown. */
async function show(id, name) {
  const { page } = v;
  await page.locator(`#mesh-list li.mesh[data-mesh-id="${id}"]`).click();
  await page.waitForFunction((meshId) => window.__cgview.lastLoaded?.id === meshId, id, { timeout: 30000 });
  await page.locator('#report h3', { hasText: name }).waitFor({ timeout: 10000 });
}

test('the boxes made here: the same box, one of positive volume and one of negative volume', () => {
  assert.ok(Math.abs(signedVolume(OUTWARD) - 2) < 1e-12, `outward: ${signedVolume(OUTWARD)}`);
  assert.ok(Math.abs(signedVolume(INWARD) + 2) < 1e-12, `inward: ${signedVolume(INWARD)}`);
});

test('uploaded, the inward box is reported as facing inward, with a warning; the outward box is not', async () => {
  const inward = await upload('box_inward.off', off(INWARD));
  const outward = await upload('box_outward.off', off(OUTWARD));
  inwardId = inward.id;
  outwardId = outward.id;
  assert.equal(inward.report.faces_inward, true, JSON.stringify(inward.report));
  assert.equal(outward.report.faces_inward, false, JSON.stringify(outward.report));
  assert.ok(
    (inward.warnings ?? []).some((w) => w.includes(INWARD_WARNING)),
    `the inward box's warnings: ${JSON.stringify(inward.warnings)}`,
  );
  assert.ok(!(outward.warnings ?? []).some((w) => w.includes(INWARD_WARNING)), `the outward box's warnings: ${JSON.stringify(outward.warnings)}`);
});

test('the report panel marks the inward box as facing inward, a defect, and lists the warning', async () => {
  const { page } = v;
  await show(inwardId, 'box_inward.off');
  const row = page.locator('#report tr[data-key="faces_inward"]');
  assert.equal(await row.locator('th').innerText(), 'faces inward');
  const cell = row.locator('td');
  assert.equal(await cell.innerText(), 'yes');
  assert.equal(await cell.getAttribute('class'), 'no', 'facing inward is a defect');
  assert.ok(await page.locator('#report h4', { hasText: 'Warnings' }).isVisible(), 'a Warnings heading');
  const warning = page.locator('#report ul.warnings li', { hasText: INWARD_WARNING });
  assert.equal(await warning.count(), 1, await page.locator('#report').innerText());
  assert.ok(await warning.isVisible());
  assert.deepEqual(v.problems, [], v.describeProblems());
});

test('the report panel marks the outward box as not facing inward, and warns of nothing about it', async () => {
  const { page } = v;
  await show(outwardId, 'box_outward.off');
  const cell = page.locator('#report tr[data-key="faces_inward"] td');
  assert.equal(await cell.innerText(), 'no');
  assert.equal(await cell.getAttribute('class'), 'yes');
  assert.equal(await page.locator('#report ul.warnings li', { hasText: INWARD_WARNING }).count(), 0, await page.locator('#report').innerText());
  assert.deepEqual(v.problems, [], v.describeProblems());
});

test('the Shape Diameter Function on the inward box is done, and its job says it ran on the box turned outward', async () => {
  const { page, server } = v;
  await show(inwardId, 'box_inward.off');
  const menu = page.locator('#algorithm-menu');
  await menu.waitFor();
  await menu.selectOption('sdf');
  const form = page.locator('form.algorithm-form[data-algorithm="sdf"]');
  await form.waitFor();
  await form.locator('button.run').click();

  const li = page.locator('#jobs li.job[data-algorithm="sdf"][data-state="done"]').first();
  await li.waitFor({ timeout: 60000 }).catch(async (e) => {
    const jobs = await page.locator('#jobs').innerText();
    throw new Error(`the job never showed done: ${e.message}\njobs panel:\n${jobs}${v.describeProblems()}\n${server.log()}`);
  });
  const warning = li.locator('ul.job-warnings li').first();
  await warning.waitFor({ timeout: 10000 });
  assert.ok(await warning.isVisible(), 'the warning is shown with the job');
  const text = await warning.innerText();
  assert.ok(text.includes(INWARD_WARNING), `the job's first warning: ${text}`);
  assert.ok(text.includes('turned outward'), `the job's first warning: ${text}`);

  // The server's job agrees: done, on the inward box, the same warning first, a colour map as usual.
  const jobId = await li.getAttribute('data-job-id');
  const jobs = (await (await fetch(`${server.url}/api/v1/jobs`)).json()).jobs;
  const job = jobs.find((j) => j.id === jobId);
  assert.ok(job, `GET /api/v1/jobs lists the job: ${JSON.stringify(jobs)}`);
  assert.equal(job.state, 'done', JSON.stringify(job));
  assert.equal(job.algorithm, 'sdf');
  assert.ok(job.warnings?.[0]?.includes(INWARD_WARNING) && job.warnings[0].includes('turned outward'), `the job's warnings: ${JSON.stringify(job.warnings)}`);
  assert.ok(!job.warnings.some((w) => w.includes('no ray that found the inside')), `turned outward, every face's rays find the inside: ${JSON.stringify(job.warnings)}`);
  assert.ok(
    job.artifacts.some((a) => a.kind === 'scalar_field' && a.name === 'sdf'),
    `the job has the sdf field: ${JSON.stringify(job.artifacts)}`,
  );
  await page.waitForFunction((id) => window.__cgview.lastField?.jobId === id, jobId, { timeout: 30000 });
  assert.equal(await page.evaluate(() => window.__cgview.lastField.meshId), inwardId, 'the colour map is drawn on the inward box');
  assert.deepEqual(v.problems, [], v.describeProblems());
});
