// End-to-end test of algorithms and jobs in the viewer (protocol/API.md
// "Algorithms and jobs"), against the real server: the algorithm menu and the
// form generated from centroid_distance's params schema, a 400 shown beside
// the form, and a job run on the elephant: the job panel goes to done, the
// canvas shows a colour map (several distinct hues, no longer the plain
// orange) and the legend. The canvas is kept in
// build/test-artifacts/e2e-jobs-elephant.png.
//
// Every test here skips, saying why, when GET /api/v1/algorithms answers 404
// (a server built before the jobs API); any other answer runs them.
//
// Environment: CGVIEW_SERVER (default build/bin/cgview-server),
// CHROMIUM (default /usr/bin/chromium).
import { after, before, test } from 'node:test';
import assert from 'node:assert/strict';
import fs from 'node:fs';
import path from 'node:path';
import { chromiumBin, dist, hueStats, launchBrowser, pngPixels, repo, serverBin, startServer } from './harness.mjs';

const elephant = path.join(repo, 'build', 'samples', 'elephant.off');
const artifacts = path.join(repo, 'build', 'test-artifacts');
const ELEPHANT = { vertices: 2775, faces: 5558 };

let server = null;
let browser = null;
let page = null;
let baseUrl = null;
let algorithmsStatus = null;
let elephantId = null;
const pageProblems = [];

const describeProblems = () => (pageProblems.length ? `\npage problems:\n${pageProblems.join('\n')}` : '');

function skipWithoutApi(t) {
  if (algorithmsStatus === 404) {
    t.skip(`the server (${serverBin}) has no jobs API yet: GET /api/v1/algorithms answered 404`);
    return true;
  }
  return false;
}

before(async () => {
  for (const [what, file] of [
    ['the server', serverBin],
    ['the built web client', path.join(dist, 'index.html')],
    ['the elephant sample', elephant],
    ['chromium', chromiumBin],
  ]) {
    assert.ok(fs.existsSync(file), `${what} is missing: ${file}`);
  }
  fs.mkdirSync(artifacts, { recursive: true });
  server = await startServer({ tmpPrefix: 'cgview-e2e-jobs-' });
  baseUrl = server.url;
  algorithmsStatus = (await fetch(`${baseUrl}/api/v1/algorithms`)).status;

  browser = await launchBrowser();
  page = await browser.newPage({ viewport: { width: 1280, height: 800 } });
  page.on('pageerror', (e) => pageProblems.push(`pageerror: ${e.message}`));
  page.on('console', (m) => {
    if (m.type() === 'error') pageProblems.push(`console.error: ${m.text()} (${m.location().url})`);
  });
  page.on('response', (r) => {
    if (r.status() >= 400) pageProblems.push(`HTTP ${r.status()}: ${r.request().method()} ${r.url()}`);
  });
  await page.goto(baseUrl + '/');
  await page.waitForFunction(() => window.__cgview?.ready === true, null, { timeout: 30000 });
  if (algorithmsStatus === 404) return;

  // The elephant, uploaded by another client: the page lists it; a click shows it.
  const r = await fetch(`${baseUrl}/api/v1/meshes?name=elephant.off`, { method: 'POST', body: fs.readFileSync(elephant) });
  assert.equal(r.status, 201, await r.clone().text());
  elephantId = (await r.json()).id;
  await page.locator(`#mesh-list li.mesh[data-mesh-id="${elephantId}"]`).click();
  await page.waitForFunction((id) => window.__cgview.lastLoaded?.id === id, elephantId, { timeout: 60000 });
});

after(async () => {
  try {
    if (browser) await browser.close();
  } finally {
    if (server) await server.stop();
  }
});

test('the algorithm menu lists centroid_distance and renders its form from the params schema', async (t) => {
  if (skipWithoutApi(t)) return;
  assert.equal(algorithmsStatus, 200, 'GET /api/v1/algorithms');
  assert.equal(await page.evaluate(() => window.__cgview.algorithmsApi), true);
  const menu = page.locator('#algorithm-menu');
  await menu.waitFor();
  const names = await menu.locator('option').evaluateAll((os) => os.map((o) => o.value));
  assert.ok(names.includes('centroid_distance'), `the menu lists centroid_distance: ${names}`);
  await menu.selectOption('centroid_distance');

  const form = page.locator('form.algorithm-form[data-algorithm="centroid_distance"]');
  await form.waitFor();
  const exponent = form.locator('input[data-param="exponent"]');
  assert.equal(await exponent.getAttribute('type'), 'number');
  assert.equal(Number(await exponent.getAttribute('min')), 0.1);
  assert.equal(Number(await exponent.getAttribute('max')), 4);
  assert.equal(Number(await exponent.inputValue()), 1, 'the default');
  const normalize = form.locator('input[data-param="normalize"]');
  assert.equal(await normalize.getAttribute('type'), 'checkbox');
  assert.equal(await normalize.isChecked(), false, 'the default');
  // Titles as labels, descriptions as help.
  const text = await form.innerText();
  for (const s of ['Exponent', 'Normalize', 'raise each distance to this power', 'divide by the largest distance']) {
    assert.ok(text.includes(s), `the form shows "${s}":\n${text}`);
  }
  assert.equal(await form.locator('button.run').isEnabled(), true, 'Run is enabled with the elephant selected');
});

test("a parameter out of range shows the server's 400 detail beside the form", async (t) => {
  if (skipWithoutApi(t)) return;
  const form = page.locator('form.algorithm-form[data-algorithm="centroid_distance"]');
  await form.locator('input[data-param="exponent"]').fill('9');
  await form.locator('button.run').click();
  const error = form.locator('.form-error');
  await error.waitFor({ state: 'visible', timeout: 15000 });
  const text = await error.innerText();
  assert.match(text, /exponent/, `the detail names the parameter: ${text}`);
  await form.locator('input[data-param="exponent"]').fill('1');
  pageProblems.length = 0; // the 400 is logged by chromium as a failed resource
});

const hues = async (png) => hueStats(await pngPixels(page, png));

test('running centroid_distance on the elephant: the job goes to done and the mesh gets a colour map and a legend', async (t) => {
  if (skipWithoutApi(t)) return;
  // Record the states and stages the job panel shows.
  await page.evaluate(() => {
    const seen = (window.__jobStates = []);
    const root = document.getElementById('jobs');
    new MutationObserver(() => {
      for (const li of root.querySelectorAll('li.job')) {
        const s = `${li.dataset.state}:${li.querySelector('.job-stage')?.textContent ?? ''}:${li.querySelector('progress')?.value}`;
        if (seen.at(-1) !== s) seen.push(s);
      }
    }).observe(root, { childList: true, subtree: true, attributes: true, characterData: true });
  });
  // The mesh was streamed once: the field is drawn on it, not on a second download.
  const asked = [];
  const onRequest = (r) => asked.push(r.url());
  page.on('request', onRequest);
  t.after(() => page.off('request', onRequest));
  const form = page.locator('form.algorithm-form[data-algorithm="centroid_distance"]');
  await form.locator('input[data-param="exponent"]').fill('1.5');
  await form.locator('button.run').click();

  const job = page.locator('#jobs li.job').first();
  await job.waitFor({ timeout: 15000 });
  await page
    .locator('#jobs li.job[data-state="done"]')
    .first()
    .waitFor({ timeout: 60000 })
    .catch(async (e) => {
      const states = await page.evaluate(() => window.__jobStates);
      throw new Error(`the job never showed done: ${e.message}\nstates: ${states}${describeProblems()}\n${server.log()}`);
    });
  const states = await page.evaluate(() => window.__jobStates);
  t.diagnostic(`job panel (state:stage:bar): ${states.join(' → ')}`);
  assert.ok(states.length >= 1 && states.at(-1).startsWith('done:'), `job panel states: ${states}`);
  for (const s of states) assert.match(s, /^(queued|running|done):/, `no failure on the way: ${states}`);
  const done = page.locator('#jobs li.job[data-state="done"]').first();
  assert.equal(await done.locator('progress').evaluate((p) => p.value), 1, 'the bar is full');
  assert.match(await done.locator('.job-percent').innerText(), /100%/);

  // The server's Job agrees.
  const jobs = (await (await fetch(`${baseUrl}/api/v1/jobs`)).json()).jobs;
  const panelId = await done.getAttribute('data-job-id');
  const ours = jobs.find((j) => j.id === panelId);
  assert.ok(ours, `GET /api/v1/jobs lists the job: ${JSON.stringify(jobs)}`);
  assert.equal(ours.state, 'done');
  const field = ours.artifacts.find((a) => a.kind === 'scalar_field');
  assert.ok(field, `the job has a scalar_field artifact: ${JSON.stringify(ours.artifacts)}`);

  // The colour map is drawn: values for every vertex, the legend shown.
  await page
    .waitForFunction(() => window.__cgview.lastField !== null, null, { timeout: 30000 })
    .catch(async (e) => {
      const error = await page.evaluate(() => window.__cgview.lastError);
      throw new Error(`no field drawn (page error: ${error}): ${e.message}${describeProblems()}`);
    });
  const shown = await page.evaluate(() => window.__cgview.lastField);
  assert.equal(shown.jobId, ours.id);
  assert.equal(shown.artifact, field.name);
  assert.equal(shown.meshId, elephantId);
  assert.equal(shown.location, 'vertex');
  assert.equal(shown.count, ELEPHANT.vertices, 'one value per vertex');
  assert.deepEqual(
    asked.filter((u) => /\/download\b/.test(u)),
    [],
    'no second download of the mesh',
  );
  assert.ok(
    asked.some((u) => u.includes(`/meshes/${elephantId}/stored_order`)),
    `the stream's stored order was asked for: ${asked.join(' ')}`,
  );
  assert.equal(shown.map, 'turbo', 'a distance (hint magnitude) is drawn on turbo');
  const legend = page.locator('#legend');
  assert.ok(await legend.isVisible(), 'the legend is shown');
  const lo = Number(await legend.locator('.legend-min').innerText());
  const hi = Number(await legend.locator('.legend-max').innerText());
  assert.ok(Number.isFinite(lo) && Number.isFinite(hi) && hi > lo, `legend range ${lo}..${hi}`);
  assert.match(await legend.locator('.legend-bar').evaluate((b) => b.style.background), /gradient/);

  const canvas = page.locator('#viewport canvas');
  const png = await canvas.screenshot({ path: path.join(artifacts, 'e2e-jobs-elephant.png') });
  const h = await hues(png);
  assert.ok(h.saturated > 5000, `coloured pixels: ${JSON.stringify(h)}`);
  assert.ok(h.distinct >= 3, `several distinct hues on the mesh: ${JSON.stringify(h)}`);
  assert.ok(h.orange < 0.5, `no longer the plain orange surface: ${JSON.stringify(h)}`);

  // Another colour map from the legend recolours the same field.
  await legend.locator('select.legend-map').selectOption('magma');
  await page.waitForFunction(() => window.__cgview.lastField?.map === 'magma', null, { timeout: 10000 });
  assert.deepEqual(pageProblems, [], describeProblems());
});

test('the same mesh, algorithm and parameters again give the cached result at once', async (t) => {
  if (skipWithoutApi(t)) return;
  const before = await page.locator('#jobs li.job').count();
  const form = page.locator('form.algorithm-form[data-algorithm="centroid_distance"]');
  await form.locator('input[data-param="exponent"]').fill('1.5');
  await form.locator('button.run').click();
  await page.waitForFunction((n) => document.querySelectorAll('#jobs li.job').length > n, before, { timeout: 15000 });
  // The newest job is listed first: done at once, marked cached, its field shown.
  const first = page.locator('#jobs li.job').first();
  assert.equal(await first.getAttribute('data-state'), 'done');
  assert.match(await first.locator('.job-state').innerText(), /cached/);
  const id = await first.getAttribute('data-job-id');
  await page.waitForFunction((jobId) => window.__cgview.lastField?.jobId === jobId, id, { timeout: 30000 });
  assert.deepEqual(pageProblems, [], describeProblems());
});

// A small job can end before the answer to its submission comes back (its
// job_done event first, on a loaded machine): what a run shows when done is
// still shown. The answer is held here until the page lists the job as done.
test('a job whose end arrives before the answer to its submission still shows its field', async (t) => {
  if (skipWithoutApi(t)) return;
  let held = null;
  const hold = async (route) => {
    if (route.request().method() !== 'POST') return route.continue();
    const response = await route.fetch();
    held = (await response.json()).id;
    await page.locator(`#jobs li.job[data-job-id="${held}"][data-state="done"]`).waitFor({ timeout: 30000 });
    await route.fulfill({ response });
  };
  await page.route('**/api/v1/jobs', hold);
  t.after(() => page.unroute('**/api/v1/jobs', hold));
  const form = page.locator('form.algorithm-form[data-algorithm="centroid_distance"]');
  await form.locator('input[data-param="exponent"]').fill('2.5');
  await form.locator('button.run').click();
  for (const until = Date.now() + 30000; !held && Date.now() < until;) await new Promise((r) => setTimeout(r, 20));
  assert.ok(held, 'the submission was answered');
  await page
    .waitForFunction((jobId) => window.__cgview.lastField?.jobId === jobId, held, { timeout: 30000 })
    .catch(async (e) => {
      throw new Error(`the field of ${held} was not drawn: ${e.message}${describeProblems()}`);
    });
  assert.deepEqual(pageProblems, [], describeProblems());
});
