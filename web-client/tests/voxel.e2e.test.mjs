// End-to-end test of voxel slices in the viewer, against the real
// server: voxelize run from the generated form, then the job's grid artifact
// opened in the slice panel: the slice comes over the WebSocket (get_slice,
// a zlib voxel-slice frame), is drawn in the 2D canvas and as a plane in the
// 3D view; the slider moves it, the checkbox cuts the mesh at it. The page is
// kept in build/test-artifacts/e2e-voxel-slice.png.
//
// Environment: CGVIEW_SERVER (default build/bin/cgview-server),
// CHROMIUM (default /usr/bin/chromium).
import { test } from 'node:test';
import assert from 'node:assert/strict';
import path from 'node:path';
import { artifactsDir as artifacts, useViewer, repo } from './harness.mjs';

const elephant = path.join(repo, 'build', 'samples', 'elephant.off');

// The viewer (server, page, problems), open for this file's tests.
const v = useViewer({ tmpPrefix: 'cgview-e2e-voxel-', mesh: elephant, httpErrors: false });

// Lit (occupied) pixels of the slice canvas.
const litPixels = () =>
  v.page.evaluate(() => {
    const c = document.querySelector('#voxel-slices canvas.slice-canvas');
    if (!c || c.width < 2) return -1;
    const { data } = c.getContext('2d').getImageData(0, 0, c.width, c.height);
    let n = 0;
    for (let i = 0; i < data.length; i += 4) n += data[i + 2] === 230 ? 1 : 0;
    return n;
  });

test('voxelize, then its grid in the slice panel: a slice drawn in 2D and in 3D, moved by the slider', async () => {
  const menu = v.page.locator('#algorithm-menu');
  await menu.waitFor();
  await menu.selectOption('voxelize');
  const form = v.page.locator('form.algorithm-form[data-algorithm="voxelize"]');
  await form.waitFor();
  await form.locator('input[data-param="resolution"]').fill('48');
  await form.locator('button.run').click();
  await v.page
    .locator('#jobs li.job[data-state="done"]')
    .first()
    .waitFor({ timeout: 60000 })
    .catch((e) => {
      throw new Error(`the voxelize job never showed done: ${e.message}${v.describeProblems()}\n${v.server.log()}`);
    });
  const slices = v.page.locator('#jobs .artifact-voxel_grid button.slices').first();
  await slices.click();
  const panel = v.page.locator('#voxel-slices');
  await panel.waitFor({ state: 'visible' });
  await v.page.waitForFunction(() => Number(document.querySelector('#voxel-slices input[type=range]')?.max ?? 0) > 0, null, {
    timeout: 30000,
  });
  // The first answer sets the slider's range, then the middle slice is fetched.
  await v.page.waitForFunction(() => {
    const c = document.querySelector('#voxel-slices canvas.slice-canvas');
    return c && c.width > 1;
  });
  await v.page.waitForTimeout(500);
  const middle = await litPixels();
  assert.ok(middle > 20, `the middle slice of the elephant shows its section: ${middle} lit voxels${v.describeProblems()}`);
  const max = Number(await panel.locator('input[type=range]').first().getAttribute('max'));
  assert.ok(max >= 20, `the slider runs over the grid: max ${max}`);
  // The first slice (padding) is empty.
  await panel.locator('input[type=range]').first().fill('0');
  await v.page.waitForFunction(() => document.querySelector('#voxel-slices .slice-label')?.textContent?.startsWith('0 /'), null, {
    timeout: 15000,
  });
  await v.page.waitForTimeout(300);
  assert.equal(await litPixels(), 0, 'slice 0 is padding');
  // Another axis, then the section view.
  await panel.locator('button', { hasText: /^x$/ }).click();
  await v.page.waitForTimeout(800);
  assert.ok((await litPixels()) > 20, `the middle x slice shows a section${v.describeProblems()}`);
  await panel.locator('input[aria-label="Cut the mesh at the slice"]').check();
  await v.page.waitForTimeout(500);
  const overlay = await v.page.evaluate(() => window.__cgview !== undefined);
  assert.ok(overlay);
  await v.page.screenshot({ path: path.join(artifacts, 'e2e-voxel-slice.png') });
  assert.deepEqual(v.problems, [], v.describeProblems());
});

test('the voxels above the threshold in 3D: every occupied voxel kept, its boundary drawn as cubes', async () => {
  const panel = v.page.locator('#voxel-slices');
  await panel.locator('input.voxels-3d').check();
  await v.page
    .waitForFunction(() => window.__cgview.lastVoxels !== null, null, { timeout: 30000 })
    .catch((e) => {
      throw new Error(`no voxels drawn: ${e.message}${v.describeProblems()}`);
    });
  const shown = await v.page.evaluate(() => window.__cgview.lastVoxels);
  const jobId = await v.page.locator('#jobs li.job[data-state="done"]').first().getAttribute('data-job-id');
  const metrics = await (await fetch(`${v.server.url}/api/v1/jobs/${jobId}/artifacts/metrics?format=json`)).json();
  assert.equal(shown.kept, metrics.occupied_voxels, `every occupied voxel is kept: ${JSON.stringify(shown)}`);
  assert.ok(shown.count > 100 && shown.count < shown.kept, `only the boundary voxels are drawn: ${JSON.stringify(shown)}`);
  await v.page.screenshot({ path: path.join(artifacts, 'e2e-voxel-3d.png') });
  // Unchecked: gone.
  await panel.locator('input.voxels-3d').uncheck();
  await v.page.waitForFunction(() => window.__cgview.lastVoxels === null, null, { timeout: 10000 });
  assert.deepEqual(v.problems, [], v.describeProblems());
});
