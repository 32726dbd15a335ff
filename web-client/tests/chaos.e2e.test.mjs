// End-to-end test of chaos_animate in the viewer (chaotic maps, docs/CHAOS.md),
// against the real server: the job is run from the generated form on the
// elephant, its animation artifact (.frames) is played, and moving the
// slider changes the positions drawn (window.__cgview.lastAnimation, set
// after the frame is rendered); "Play" in the job list and the player's
// play button advance the frames. The canvas at the last frame is kept in
// build/test-artifacts/e2e-chaos-animate.png.
// A message hidden by chaos_embed and read back by a chained chaos_extract
// (submitted over REST by another client) shows in the job panel.
//
// Environment: CGVIEW_SERVER (default build/bin/cgview-server),
// CHROMIUM (default /usr/bin/chromium).
import { test } from 'node:test';
import assert from 'node:assert/strict';
import fs from 'node:fs';
import path from 'node:path';
import { artifactsDir as artifacts, useViewer, repo } from './harness.mjs';

const elephant = path.join(repo, 'build', 'samples', 'elephant.off');

// The viewer (server, page, problems), open for this file's tests.
const v = useViewer({ tmpPrefix: 'cgview-e2e-chaos-', mesh: elephant, httpErrors: false });

test('chaos_animate from the form: the slider and the play button change the positions drawn', async () => {
  const menu = v.page.locator('#algorithm-menu');
  await menu.waitFor();
  await menu.selectOption('chaos_animate');
  const form = v.page.locator('form.algorithm-form[data-algorithm="chaos_animate"]');
  await form.waitFor();
  await form.locator('[data-param="frames"]').fill('8');
  await form.locator('button.run').click();
  const done = v.page.locator('#jobs li.job[data-state="done"]').first();
  await done.waitFor({ timeout: 60000 }).catch((e) => {
    throw new Error(`chaos_animate never showed done: ${e.message}${v.describeProblems()}\n${v.server.log()}`);
  });
  const row = done.locator('.artifact-animation');
  // "Play" plays the frames through at once, and stops on the last one.
  await row.locator('button.play-animation').click();
  await v.page.waitForFunction(() => window.__cgview.lastAnimation?.frame === 8, null, { timeout: 30000 });
  await v.page.locator('#animation-player button.player-play', { hasText: 'Play' }).waitFor({ timeout: 5000 });
  const slider = v.page.locator('#animation-player input.player-slider');
  await slider.fill('0');
  await v.page.waitForFunction(() => window.__cgview.lastAnimation?.frame === 0, null, { timeout: 10000 });
  const first = await v.page.evaluate(() => window.__cgview.lastAnimation);
  assert.equal(first.frames, 9, 'frame 0 (the input) and 8 steps');
  assert.equal(first.vertices, 2775);

  await slider.fill('5');
  await v.page.waitForFunction(() => window.__cgview.lastAnimation?.frame === 5, null, { timeout: 10000 });
  const fifth = await v.page.evaluate(() => window.__cgview.lastAnimation);
  assert.notDeepEqual(fifth.first, first.first, 'the first vertex moved');
  assert.ok(Math.abs(fifth.sum - first.sum) > 1e-3, `the positions changed: sums ${first.sum} and ${fifth.sum}`);
  assert.match(await v.page.locator('#animation-player .player-frame').innerText(), /step 5 \/ 8/);

  await slider.fill('0');
  await v.page.waitForFunction(() => window.__cgview.lastAnimation?.frame === 0, null, { timeout: 10000 });
  assert.equal((await v.page.evaluate(() => window.__cgview.lastAnimation)).sum, first.sum, 'back to frame 0');

  await v.page.locator('#animation-player button.player-play').click();
  await v.page.waitForFunction(() => window.__cgview.lastAnimation?.frame === 8, null, { timeout: 20000 });
  assert.equal(await v.page.locator('#animation-player button.player-play').innerText(), 'Play', 'stopped at the end');
  fs.writeFileSync(path.join(artifacts, 'e2e-chaos-animate.png'), await v.page.locator('#viewport canvas').screenshot());
  assert.deepEqual(v.problems, [], v.describeProblems());
});

async function runJob(body) {
  const r = await fetch(`${v.server.url}/api/v1/jobs`, { method: 'POST', body: JSON.stringify(body) });
  assert.equal(r.status, 201, await r.clone().text());
  const id = (await r.json()).id;
  for (let i = 0; i < 600; ++i) {
    const job = await (await fetch(`${v.server.url}/api/v1/jobs/${id}`)).json();
    if (job.state === 'done' || job.state === 'failed') return job;
    await new Promise((res) => setTimeout(res, 100));
  }
  throw new Error(`job ${id} did not finish`);
}

test('a message extracted by chaos_extract shows in the job panel', async () => {
  const message = 'Figure 11, hidden in the elephant — ünïcödé';
  const embed = await runJob({ algorithm: 'chaos_embed', inputs: { mesh: v.meshId }, params: { key: 'k', message } });
  assert.equal(embed.state, 'done', JSON.stringify(embed));
  const extract = await runJob({ algorithm: 'chaos_extract', inputs: { mesh: { job: embed.id, artifact: 'mesh' } }, params: { key: 'k' } });
  assert.equal(extract.state, 'done', JSON.stringify(extract));
  const text = v.page.locator(`#jobs li.job[data-job-id="${extract.id}"] .text-content`);
  await text.waitFor({ timeout: 20000 });
  await v.page.waitForFunction((id) => !document.querySelector(`#jobs li.job[data-job-id="${id}"] .text-content`)?.textContent?.includes('loading'), extract.id, {
    timeout: 10000,
  });
  assert.equal(await text.innerText(), message);
  assert.deepEqual(v.problems, [], v.describeProblems());
});
