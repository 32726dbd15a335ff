// End-to-end test of a long job in the viewer: progress arriving over the
// WebSocket, the Cancel button (POST /api/v1/jobs/{id}/cancel), and the
// ended job's Delete button (DELETE /api/v1/jobs/{id}). It needs a slow
// algorithm, so it runs the server with the test worker (cgview-worker-test
// beside the server binary, whose test_sleep runs for a given time; the
// server keeps test algorithms out of GET /api/v1/algorithms, so the test
// submits it over REST, as another client would). The second test starts it
// from the form instead (a page whose algorithm list gets it added): Run
// busy, the progress and Cancel under it in view at 1280x800, Run back after.
//
// Skips, saying why, when GET /api/v1/algorithms answers 404 (no jobs API) or
// when cgview-worker-test is not built beside the server.
import { after, before, test } from 'node:test';
import assert from 'node:assert/strict';
import fs from 'node:fs';
import path from 'node:path';
import { dist, launchBrowser, repo, serverBin, startServer } from './harness.mjs';

const elephant = path.join(repo, 'build', 'samples', 'elephant.off');
const testWorker = path.join(path.dirname(serverBin), 'cgview-worker-test');
const artifacts = path.join(repo, 'build', 'test-artifacts');

let server = null;
let browser = null;
let page = null;
let skipReason = null;
const pageProblems = [];

before(async () => {
  assert.ok(fs.existsSync(path.join(dist, 'index.html')), 'the built web client');
  if (!fs.existsSync(testWorker)) {
    skipReason = `the test worker is not built: ${testWorker}`;
    return;
  }
  server = await startServer({ tmpPrefix: 'cgview-e2e-cancel-', extraArgs: ['--samples', 'none', '--worker', testWorker] });
  const status = (await fetch(`${server.url}/api/v1/algorithms`)).status;
  if (status === 404) {
    skipReason = `the server (${serverBin}) has no jobs API yet: GET /api/v1/algorithms answered 404`;
    return;
  }
  browser = await launchBrowser();
  page = await browser.newPage({ viewport: { width: 1280, height: 800 } });
  page.on('pageerror', (e) => pageProblems.push(`pageerror: ${e.message}`));
  page.on('console', (m) => {
    if (m.type() === 'error') pageProblems.push(`console.error: ${m.text()} (${m.location().url})`);
  });
  await page.goto(server.url + '/');
  await page.waitForFunction(() => window.__cgview?.ready === true, null, { timeout: 30000 });
});

after(async () => {
  try {
    if (browser) await browser.close();
  } finally {
    if (server) await server.stop();
  }
});

test('a long job shows its progress live and the Cancel button cancels it', async (t) => {
  if (skipReason) {
    t.skip(skipReason);
    return;
  }
  const r = await fetch(`${server.url}/api/v1/meshes?name=elephant.off`, { method: 'POST', body: fs.readFileSync(elephant) });
  assert.equal(r.status, 201, await r.clone().text());
  const meshId = (await r.json()).id;
  await page.locator(`#mesh-list li.mesh[data-mesh-id="${meshId}"]`).click();
  await page.waitForFunction((id) => window.__cgview.lastLoaded?.id === id, meshId, { timeout: 60000 });

  // test_sleep is hidden from the menu (area "test"), so another client submits
  // it; the page learns of it from the job_* events.
  const menu = page.locator('#algorithm-menu');
  const names = await menu.locator('option').evaluateAll((os) => os.map((o) => o.value));
  assert.ok(!names.includes('test_sleep'), `test algorithms stay out of the menu: ${names}`);
  const submitted = await fetch(`${server.url}/api/v1/jobs`, {
    method: 'POST',
    headers: { 'Content-Type': 'application/json' },
    body: JSON.stringify({ algorithm: 'test_sleep', inputs: { mesh: meshId }, params: { seconds: 30 } }),
  });
  assert.equal(submitted.status, 201, await submitted.clone().text());

  // Running, with the bar moving (job_progress events over the WebSocket).
  const job = page.locator('#jobs li.job[data-state="running"]').first();
  await job.waitFor({ timeout: 20000 });
  const id = await job.getAttribute('data-job-id');
  const item = page.locator(`#jobs li.job[data-job-id="${id}"]`);
  await page.waitForFunction(
    (jobId) => {
      const li = document.querySelector(`#jobs li.job[data-job-id="${jobId}"]`);
      return li && li.querySelector('progress').value > 0.02;
    },
    id,
    { timeout: 20000 },
  );
  const first = await item.locator('progress').evaluate((p) => p.value);
  assert.match(await item.locator('.job-stage').innerText(), /\S/, 'a stage name is shown');
  await page.waitForFunction(({ jobId, v }) => document.querySelector(`#jobs li.job[data-job-id="${jobId}"] progress`).value > v, { jobId: id, v: first }, { timeout: 20000 });

  fs.mkdirSync(artifacts, { recursive: true });
  await page.screenshot({ path: path.join(artifacts, 'e2e-jobs-running.png') });
  await item.locator('button.cancel').click();
  await page.locator(`#jobs li.job[data-job-id="${id}"][data-state="cancelled"]`).waitFor({ timeout: 15000 });
  assert.equal(await page.locator(`#jobs li.job[data-job-id="${id}"] button.cancel`).count(), 0, 'no Cancel once cancelled');
  const body = await (await fetch(`${server.url}/api/v1/jobs/${id}`)).json();
  assert.equal(body.state, 'cancelled');
  assert.equal(await page.evaluate(() => window.__cgview.lastField), null, 'no field drawn');
  assert.ok(await page.locator('#legend').isHidden(), 'no legend');

  // An ended job is deleted with its Delete button: gone from the list and from the server.
  await page.locator(`#jobs li.job[data-job-id="${id}"] button.delete`).click();
  await page.locator(`#jobs li.job[data-job-id="${id}"]`).waitFor({ state: 'detached', timeout: 15000 });
  assert.equal((await fetch(`${server.url}/api/v1/jobs/${id}`)).status, 404, 'the server forgot it');
  assert.deepEqual(pageProblems, [], pageProblems.join('\n'));
});

// test_sleep as the menu would list it if the server listed test algorithms:
// this page's GET /api/v1/algorithms gets it added, so that the student's own
// form starts the slow job (the server runs it as any other).
const SLEEP = {
  name: 'test_sleep',
  title: 'Sleep (test)',
  area: 'test',
  description: 'runs for a while, checking for cancellation',
  inputs: [{ name: 'mesh', kind: 'mesh', description: 'the mesh to process' }],
  outputs: [{ name: 'index', kind: 'scalar_field' }],
  params: {
    type: 'object',
    additionalProperties: false,
    properties: { seconds: { type: 'number', title: 'Seconds', description: 'how long to run', default: 30, minimum: 0, maximum: 3600 } },
  },
};

test('a job started from the form shows Run busy, its progress and a Cancel beside the form, in view at 1280x800', async (t) => {
  if (skipReason) {
    t.skip(skipReason);
    return;
  }
  const r = await fetch(`${server.url}/api/v1/meshes?name=elephant-form.off`, { method: 'POST', body: fs.readFileSync(elephant) });
  assert.equal(r.status, 201, await r.clone().text());
  const meshId = (await r.json()).id;
  const problems = [];
  const own = await browser.newPage({ viewport: { width: 1280, height: 800 } });
  try {
    own.on('pageerror', (e) => problems.push(`pageerror: ${e.message}`));
    own.on('console', (m) => {
      if (m.type() === 'error') problems.push(`console.error: ${m.text()} (${m.location().url})`);
    });
    await own.route('**/api/v1/algorithms', async (route) => {
      const response = await route.fetch();
      const body = await response.json();
      body.algorithms.push(SLEEP);
      await route.fulfill({ response, json: body });
    });
    await own.goto(server.url + '/');
    await own.waitForFunction(() => window.__cgview?.ready === true, null, { timeout: 30000 });
    await own.locator(`#mesh-list li.mesh[data-mesh-id="${meshId}"]`).click();
    await own.waitForFunction((id) => window.__cgview.lastLoaded?.id === id, meshId, { timeout: 60000 });
    await own.locator('#algorithm-menu').selectOption('test_sleep');
    const form = own.locator('form.algorithm-form[data-algorithm="test_sleep"]');
    await form.waitFor({ timeout: 10000 });
    const run = form.locator('button.run');
    const seconds = form.locator('#param-test_sleep-seconds');
    await seconds.fill('30');
    await run.click();

    // Run is busy while its job runs, and says so.
    await own.waitForFunction(() => document.querySelector('form.algorithm-form button.run')?.getAttribute('aria-busy') === 'true', null, { timeout: 10000 });
    assert.equal(await run.innerText(), 'Running…');
    assert.equal(await run.isDisabled(), true, 'the same run cannot be queued twice by a second click');

    // Its progress beside the form: a line with the stage, the percentage and Cancel, inside the 1280x800 viewport, moving.
    const line = form.locator('.run-progress .run-job');
    await line.waitFor({ timeout: 20000 });
    const id = await line.getAttribute('data-job-id');
    await own.waitForFunction(() => document.querySelector('.run-progress .run-job progress')?.value > 0.02, null, { timeout: 20000 });
    const box = await form.locator('.run-progress').boundingBox();
    assert.ok(box && box.x >= 0 && box.y >= 0 && box.x + box.width <= 1280 && box.y + box.height <= 800, `the progress is in view: ${JSON.stringify(box)}`);
    const cancelBox = await line.locator('button.cancel').boundingBox();
    assert.ok(cancelBox && cancelBox.y + cancelBox.height <= 800 && cancelBox.x + cancelBox.width <= 1280, `Cancel is in view: ${JSON.stringify(cancelBox)}`);
    assert.match(await line.locator('.run-job-stage').innerText(), /sleeping/, 'the stage the worker names');
    const first = await line.locator('progress').evaluate((p) => p.value);
    await own.waitForFunction((v) => document.querySelector('.run-progress .run-job progress')?.value > v, first, { timeout: 20000 });
    assert.match(await line.locator('.run-job-percent').innerText(), /^\d+%$/);
    // The job list shows the same job running.
    assert.equal(await own.locator(`#jobs li.job[data-job-id="${id}"]`).getAttribute('data-state'), 'running');

    // Other parameters may be run meanwhile (the server queues them); the same ones again may not.
    await seconds.fill('31');
    assert.equal(await run.innerText(), 'Run');
    assert.equal(await run.isEnabled(), true, 'another request may be queued');
    assert.equal(await run.getAttribute('aria-busy'), null);
    await seconds.fill('30');
    assert.equal(await run.innerText(), 'Running…', 'the request that runs is busy again');
    fs.mkdirSync(artifacts, { recursive: true });
    await own.screenshot({ path: path.join(artifacts, 'e2e-jobs-running-form.png') });

    // Cancel beside the form cancels it; the form is back to normal.
    await line.locator('button.cancel').click();
    await own.locator(`#jobs li.job[data-job-id="${id}"][data-state="cancelled"]`).waitFor({ timeout: 15000 });
    await form.locator('.run-progress').waitFor({ state: 'hidden', timeout: 5000 });
    assert.equal(await form.locator('.run-progress .run-job').count(), 0, 'no line for an ended job');
    assert.equal(await run.innerText(), 'Run');
    assert.equal(await run.isEnabled(), true, 'Run is back');
    assert.equal(await run.getAttribute('aria-busy'), null);
    assert.equal((await (await fetch(`${server.url}/api/v1/jobs/${id}`)).json()).state, 'cancelled');
    assert.deepEqual(problems, [], problems.join('\n'));
  } finally {
    await own.close();
  }
});
