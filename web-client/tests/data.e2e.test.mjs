// End-to-end test of data other tools made, uploaded through the page's
// upload control like a mesh (POST /api/v1/data), against the real server:
// the sphere uploaded as a mesh, then, through the same file input, a field's
// values (.txt, one a line, one per face) drawn on it with its legend and no
// warning in its import job; a field with a value missing (nan), its job
// showing the server's warning; a voxel grid (.nrrd written here) whose
// import job lists it and whose slices open; values of the wrong count,
// refused with the server's detail shown. Then a PLY whose faces carry a
// property, loaded as a field with "Load field file…" (the upload control
// takes a .ply for a mesh). The canvas with the field and the job with its
// warning are kept in build/test-artifacts/e2e-data-{field,warning}.png.
//
//   CGVIEW_SERVER=build/bin/cgview-server CGVIEW_SAMPLES=build/samples node --test tests/data.e2e.test.mjs
//
// Environment: CGVIEW_SERVER, CGVIEW_SAMPLES (default build/samples), CHROMIUM.
import { after, before, test } from 'node:test';
import assert from 'node:assert/strict';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { artifactsDir, hueStats, pngPixels, repo, settle, useViewer } from './harness.mjs';

const samples = process.env.CGVIEW_SAMPLES ?? path.join(repo, 'build', 'samples');
const sphere = path.join(samples, 'sphere.off');
const v = useViewer({ tmpPrefix: 'cgview-e2e-data-' });

let dir = null;
let mesh = null; // the sphere as the server stores it: { id, report }

before(async () => {
  assert.ok(fs.existsSync(sphere), `the sphere sample is missing: ${sphere}`);
  dir = fs.mkdtempSync(path.join(os.tmpdir(), 'cgview-e2e-data-files-'));
});

after(() => {
  if (dir) fs.rmSync(dir, { recursive: true, force: true });
});

/** Writes a file for the upload control into the test's folder; returns its path. */
function write(name, content) {
  const file = path.join(dir, name);
  fs.writeFileSync(file, content);
  return file;
}

/** The done import job of `file` in the job list (its title names the file). */
const importJob = (file) => v.page.locator('#jobs li.job[data-algorithm="import"][data-state="done"]', { has: v.page.locator(`.job-title[title*='"file":"${file}"']`) });

async function waitForImport(file) {
  const li = importJob(file);
  await li.waitFor({ timeout: 30000 }).catch(async (e) => {
    const error = await v.page.evaluate(() => window.__cgview.lastError);
    throw new Error(`no done import job of ${file} in the list (page error: ${error}): ${e.message}${v.describeProblems()}\n${v.server.log()}`);
  });
  return li;
}

async function waitForField(jobId) {
  await v.page
    .waitForFunction((id) => window.__cgview.lastField?.jobId === id, jobId, { timeout: 30000 })
    .catch(async (e) => {
      const error = await v.page.evaluate(() => window.__cgview.lastError);
      throw new Error(`the field of job ${jobId} was not drawn (page error: ${error}): ${e.message}${v.describeProblems()}`);
    });
  return v.page.evaluate(() => window.__cgview.lastField);
}

test('the sphere, uploaded through the page, is shown', async () => {
  await v.page.setInputFiles('#file-input', sphere);
  await v.page.waitForFunction(() => window.__cgview.lastLoaded !== null, null, { timeout: 60000 });
  const id = await v.page.evaluate(() => window.__cgview.lastLoaded.id);
  mesh = await (await fetch(`${v.server.url}/api/v1/meshes/${id}`)).json();
  assert.equal(mesh.name, 'sphere.off');
  assert.ok(mesh.report.faces > 100 && mesh.report.faces !== mesh.report.vertices, JSON.stringify(mesh.report));
  assert.deepEqual(v.problems, [], v.describeProblems());
});

test('a .txt of one value per face, through the upload control: an import job, no warning, the field drawn on the sphere with its legend', async () => {
  const faces = mesh.report.faces;
  const file = write('face_index.txt', Array.from({ length: faces }, (_, i) => String(i)).join('\n') + '\n');
  await v.page.setInputFiles('#file-input', file);
  const li = await waitForImport('face_index.txt');
  const jobId = await li.getAttribute('data-job-id');
  const shown = await waitForField(jobId);
  assert.deepEqual(
    { artifact: shown.artifact, meshId: shown.meshId, location: shown.location, count: shown.count, range: shown.range },
    { artifact: 'face_index', meshId: mesh.id, location: 'face', count: faces, range: [0, faces - 1] },
  );
  // What the user sees: the job's field row says Shown, no warning under the job, the legend over its range, a colour map on the sphere.
  await li.locator('.artifact-scalar_field[data-artifact="face_index"] button.show.active').waitFor({ timeout: 10000 });
  assert.equal(await li.locator('ul.job-warnings').count(), 0, 'all values given: no warning');
  const legend = v.page.locator('#legend');
  assert.ok(await legend.isVisible(), 'the legend is shown');
  assert.match(await legend.locator('.legend-title').innerText(), /import · face_index/);
  assert.equal(await legend.locator('.legend-min').innerText(), '0');
  assert.equal(await legend.locator('.legend-max').innerText(), String(faces - 1));
  assert.equal(await legend.locator('svg.legend-histogram').getAttribute('data-total'), String(faces));
  await settle(v.page);
  const png = await v.page.locator('#viewport canvas').screenshot({ path: path.join(artifactsDir, 'e2e-data-field.png') });
  const hues = hueStats(await pngPixels(v.page, png));
  assert.ok(hues.distinct >= 2 && hues.orange < 0.5, `a colour map, not the plain orange surface: ${JSON.stringify(hues)}`);
  // The server's job: an import of the file for the sphere.
  const job = await (await fetch(`${v.server.url}/api/v1/jobs/${jobId}`)).json();
  assert.deepEqual([job.params.file, job.inputs.mesh, job.warnings], ['face_index.txt', mesh.id, []]);
  assert.deepEqual(v.problems, [], v.describeProblems());
});

test("a value missing (nan): the import job shows the server's warning under it", async () => {
  const faces = mesh.report.faces;
  const lines = Array.from({ length: faces }, (_, i) => (i === 7 ? 'nan' : String(i % 10)));
  await v.page.setInputFiles('#file-input', write('with_gap.txt', lines.join('\n') + '\n'));
  const li = await waitForImport('with_gap.txt');
  const jobId = await li.getAttribute('data-job-id');
  const job = await (await fetch(`${v.server.url}/api/v1/jobs/${jobId}`)).json();
  assert.equal(job.warnings.length, 1, JSON.stringify(job));
  const warnings = li.locator('ul.job-warnings > li');
  assert.equal(await warnings.count(), 1);
  assert.equal(await warnings.innerText(), job.warnings[0]);
  assert.match(job.warnings[0], new RegExp(`1 of the ${faces} values are missing`));
  assert.ok(await warnings.isVisible(), 'the warning is visible in the job list');
  await li.screenshot({ path: path.join(artifactsDir, 'e2e-data-warning.png') });
  // The field is drawn all the same, the face without a value left out of the legend's histogram.
  const shown = await waitForField(jobId);
  assert.equal(shown.count, faces);
  await v.page.waitForFunction((n) => document.querySelector('#legend svg.legend-histogram')?.getAttribute('data-total') === String(n), faces - 1, { timeout: 10000 });
  assert.deepEqual(v.problems, [], v.describeProblems());
});

test('a voxel grid (.nrrd) through the upload control: an import job with its grid, its slices open', async () => {
  // 4×4×4 bytes, x fastest: a 2×2 column of ones through every z slice.
  const voxels = new Uint8Array(64);
  for (let z = 0; z < 4; ++z) for (let y = 1; y <= 2; ++y) for (let x = 1; x <= 2; ++x) voxels[x + 4 * (y + 4 * z)] = 1;
  const header = 'NRRD0004\ntype: uchar\ndimension: 3\nsizes: 4 4 4\nencoding: raw\n\n';
  await v.page.setInputFiles('#file-input', write('column.nrrd', Buffer.concat([Buffer.from(header, 'ascii'), Buffer.from(voxels)])));
  const li = await waitForImport('column.nrrd');
  const row = li.locator('.artifact-voxel_grid[data-artifact="grid"]');
  await row.waitFor();
  assert.equal(await row.locator('button.slices').count(), 1, 'the grid row offers its slices');
  // The slice panel opened by itself, on the middle z slice: the column's 2×2 section lit.
  const panel = v.page.locator('#voxel-slices');
  await panel.waitFor({ state: 'visible', timeout: 10000 });
  assert.equal(await panel.locator('h2').textContent(), 'Slices of grid');
  await v.page
    .waitForFunction(() => document.querySelector('#voxel-slices .slice-label')?.textContent === '2 / 3', null, { timeout: 15000 })
    .catch(async (e) => {
      throw new Error(`the middle slice never showed (label '${await panel.locator('.slice-label').innerText()}'): ${e.message}${v.describeProblems()}`);
    });
  const lit = await v.page.evaluate(() => {
    const c = document.querySelector('#voxel-slices canvas.slice-canvas');
    const { data } = c.getContext('2d').getImageData(0, 0, c.width, c.height);
    let n = 0;
    for (let i = 0; i < data.length; i += 4) n += data[i + 2] === 230 ? 1 : 0;
    return { width: c.width, height: c.height, n };
  });
  assert.deepEqual(lit, { width: 4, height: 4, n: 4 });
  assert.deepEqual(v.problems, [], v.describeProblems());
});

test("values of the wrong count: refused, the page shows the server's detail, no job added", async () => {
  const file = write('too_few.txt', '1\n2\n3\n');
  // The server's words for it, asked directly (a refused upload stores nothing).
  const answer = await fetch(`${v.server.url}/api/v1/data?name=too_few.txt&mesh=${mesh.id}`, { method: 'POST', body: fs.readFileSync(file) });
  assert.equal(answer.status, 400);
  const { detail } = await answer.json();
  assert.match(detail, /3 values/);
  const jobs = await v.page.locator('#jobs li.job').count();
  await v.page.setInputFiles('#file-input', file);
  const message = v.page.locator('#messages .message.error', { hasText: 'too_few.txt' });
  await message.waitFor({ timeout: 30000 });
  assert.ok((await message.innerText()).includes(detail), `the message says the server's detail '${detail}': ${await message.innerText()}`);
  assert.equal(await v.page.locator('#jobs li.job').count(), jobs);
  // The refusal (the 400 and the browser's console line about it) is the one error of this test.
  const problems = v.problems.splice(0);
  assert.ok(problems.length > 0 && problems.every((p) => /400.*\/api\/v1\/data/.test(p)), problems.join('\n'));
});

test('a PLY whose faces carry a property, with "Load field file…": drawn as a field, not uploaded as a mesh', async () => {
  // The sphere as an ASCII PLY, each face with its centroid's height.
  const lines = fs
    .readFileSync(sphere, 'utf8')
    .split('\n')
    .map((l) => l.trim())
    .filter((l) => l && !l.startsWith('#'));
  const [nv, nf] = lines[1].split(/\s+/).map(Number);
  const positions = lines.slice(2, 2 + nv).map((l) => l.split(/\s+/).map(Number));
  const faces = lines.slice(2 + nv, 2 + nv + nf).map((l) => l.split(/\s+/).map(Number).slice(1));
  const heights = faces.map((f) => f.reduce((s, i) => s + positions[i][2], 0) / f.length);
  const ply = [
    'ply',
    'format ascii 1.0',
    `element vertex ${nv}`,
    'property float x',
    'property float y',
    'property float z',
    `element face ${nf}`,
    'property list uchar int vertex_indices',
    'property float height',
    'end_header',
    ...positions.map((p) => p.join(' ')),
    ...faces.map((f, i) => `${f.length} ${f.join(' ')} ${heights[i]}`),
  ];
  const meshes = await v.page.locator('#mesh-list li.mesh').count();
  await v.page.locator('#skeletons button.load-field').waitFor();
  await v.page.setInputFiles('#field-file-input', write('heights.ply', ply.join('\n') + '\n'));
  const li = await waitForImport('heights.ply');
  const jobId = await li.getAttribute('data-job-id');
  const shown = await waitForField(jobId);
  assert.deepEqual([shown.artifact, shown.location, shown.count, shown.meshId], ['height', 'face', nf, mesh.id]);
  assert.equal(await v.page.locator('#mesh-list li.mesh').count(), meshes, 'no mesh was added');
  // The PLY's own geometry is not used: the job says so, as the server does.
  const job = await (await fetch(`${v.server.url}/api/v1/jobs/${jobId}`)).json();
  assert.ok(job.warnings.length > 0, JSON.stringify(job));
  assert.deepEqual(await li.locator('ul.job-warnings > li').allInnerTexts(), job.warnings);
  assert.deepEqual(v.problems, [], v.describeProblems());
});
