// End-to-end test of chaos_animate in the viewer (issue 9; docs/CHAOS.md),
// against the real server: the job is run from the generated form on the
// elephant, its animation artifact (.frames) is played, and moving the
// slider changes the positions drawn (window.__cgview.lastAnimation, set
// after the frame is rendered); the play button advances the frames.  The
// canvas at the last frame is kept in build/test-artifacts/e2e-chaos-animate.png.
// A message hidden by chaos_embed and read back by a chained chaos_extract
// (submitted over REST by another client) shows in the job panel.
//
// Environment: CGVIEW_SERVER (default build/bin/cgview-server),
// CHROMIUM (default /usr/bin/chromium).
import { after, before, test } from 'node:test';
import assert from 'node:assert/strict';
import fs from 'node:fs';
import path from 'node:path';
import { chromiumBin, dist, launchBrowser, repo, serverBin, startServer } from './harness.mjs';

const elephant = path.join(repo, 'build', 'samples', 'elephant.off');
const artifacts = path.join(repo, 'build', 'test-artifacts');

let server = null;
let browser = null;
let page = null;
let baseUrl = null;
let elephantId = null;
const pageProblems = [];
const describeProblems = () => (pageProblems.length ? `\npage problems:\n${pageProblems.join('\n')}` : '');

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
  server = await startServer({ tmpPrefix: 'cgview-e2e-chaos-' });
  baseUrl = server.url;
  browser = await launchBrowser();
  page = await browser.newPage({ viewport: { width: 1280, height: 800 } });
  page.on('pageerror', (e) => pageProblems.push(`pageerror: ${e.message}`));
  page.on('console', (m) => {
    if (m.type() === 'error') pageProblems.push(`console.error: ${m.text()} (${m.location().url})`);
  });
  await page.goto(baseUrl + '/');
  await page.waitForFunction(() => window.__cgview?.ready === true, null, { timeout: 30000 });
  const r = await fetch(`${baseUrl}/api/v1/meshes?name=elephant.off`, { method: 'POST', body: fs.readFileSync(elephant) });
  assert.equal(r.status, 201, await r.clone().text());
  elephantId = (await r.json()).id;
  await page.locator(`#mesh-list li.mesh[data-mesh-id="${elephantId}"]`).click();
  await page.waitForFunction((i) => window.__cgview.lastLoaded?.id === i, elephantId, { timeout: 60000 });
});

after(async () => {
  try {
    if (browser) await browser.close();
  } finally {
    if (server) await server.stop();
  }
});

test('chaos_animate from the form: the slider and the play button change the positions drawn', async () => {
  const menu = page.locator('#algorithm-menu');
  await menu.waitFor();
  await menu.selectOption('chaos_animate');
  const form = page.locator('form.algorithm-form[data-algorithm="chaos_animate"]');
  await form.waitFor();
  await form.locator('[data-param="frames"]').fill('8');
  await form.locator('button.run').click();
  const done = page.locator('#jobs li.job[data-state="done"]').first();
  await done.waitFor({ timeout: 60000 }).catch((e) => {
    throw new Error(`chaos_animate never showed done: ${e.message}${describeProblems()}\n${server.log()}`);
  });
  const row = done.locator('.artifact-animation');
  await row.locator('button.play-animation').click();
  await page.waitForFunction(() => window.__cgview.lastAnimation?.frame === 0, null, { timeout: 30000 });
  const first = await page.evaluate(() => window.__cgview.lastAnimation);
  assert.equal(first.frames, 9, 'frame 0 (the input) and 8 steps');
  assert.equal(first.vertices, 2775);

  const slider = page.locator('#animation-player input.player-slider');
  await slider.fill('5');
  await page.waitForFunction(() => window.__cgview.lastAnimation?.frame === 5, null, { timeout: 10000 });
  const fifth = await page.evaluate(() => window.__cgview.lastAnimation);
  assert.notDeepEqual(fifth.first, first.first, 'the first vertex moved');
  assert.ok(Math.abs(fifth.sum - first.sum) > 1e-3, `the positions changed: sums ${first.sum} and ${fifth.sum}`);
  assert.match(await page.locator('#animation-player .player-frame').innerText(), /step 5 \/ 8/);

  await slider.fill('0');
  await page.waitForFunction(() => window.__cgview.lastAnimation?.frame === 0, null, { timeout: 10000 });
  assert.equal((await page.evaluate(() => window.__cgview.lastAnimation)).sum, first.sum, 'back to frame 0');

  await page.locator('#animation-player button.player-play').click();
  await page.waitForFunction(() => window.__cgview.lastAnimation?.frame === 8, null, { timeout: 20000 });
  assert.equal(await page.locator('#animation-player button.player-play').innerText(), 'Play', 'stopped at the end');
  fs.writeFileSync(path.join(artifacts, 'e2e-chaos-animate.png'), await page.locator('#viewport canvas').screenshot());
  assert.deepEqual(pageProblems, [], describeProblems());
});

async function runJob(body) {
  const r = await fetch(`${baseUrl}/api/v1/jobs`, { method: 'POST', body: JSON.stringify(body) });
  assert.equal(r.status, 201, await r.clone().text());
  const id = (await r.json()).id;
  for (let i = 0; i < 600; ++i) {
    const job = await (await fetch(`${baseUrl}/api/v1/jobs/${id}`)).json();
    if (job.state === 'done' || job.state === 'failed') return job;
    await new Promise((res) => setTimeout(res, 100));
  }
  throw new Error(`job ${id} did not finish`);
}

test('a message extracted by chaos_extract shows in the job panel', async () => {
  const message = 'Figure 11, hidden in the elephant — ünïcödé';
  const embed = await runJob({ algorithm: 'chaos_embed', inputs: { mesh: elephantId }, params: { key: 'k', message } });
  assert.equal(embed.state, 'done', JSON.stringify(embed));
  const extract = await runJob({ algorithm: 'chaos_extract', inputs: { mesh: { job: embed.id, artifact: 'mesh' } }, params: { key: 'k' } });
  assert.equal(extract.state, 'done', JSON.stringify(extract));
  const text = page.locator(`#jobs li.job[data-job-id="${extract.id}"] .text-content`);
  await text.waitFor({ timeout: 20000 });
  await page.waitForFunction((id) => !document.querySelector(`#jobs li.job[data-job-id="${id}"] .text-content`)?.textContent?.includes('loading'), extract.id, { timeout: 10000 });
  assert.equal(await text.innerText(), message);
  assert.deepEqual(pageProblems, [], describeProblems());
});
