// End-to-end test of fields compared side by side, against the real server:
// centroid_distance (hint magnitude: drawn on turbo, with a histogram in its
// legend) and curvature (two symmetric fields) on the elephant; "Compare" on
// the curvature job shows its two fields in two panes, "Add to comparison"
// adds the distance as a third. Each pane shows its own map and legend; a
// drag in the first pane moves the one camera, so every pane changes and all
// keep the same silhouette. "Leave comparison" goes back to one view.
// The canvas is kept in build/test-artifacts/e2e-compare-*.png.
//
// Environment: CGVIEW_SERVER (default build/bin/cgview-server),
// CHROMIUM (default /usr/bin/chromium).
import { test } from 'node:test';
import assert from 'node:assert/strict';
import path from 'node:path';
import { artifactsDir as artifacts, hueStats, pngPixels, repo, useViewer } from './harness.mjs';

const elephant = path.join(repo, 'build', 'samples', 'elephant.off');
const BACKGROUND = [0x1b, 0x1d, 0x22];
// Silhouettes drawn through one camera differ at most along their edges
// (panes a pixel wider or narrower than the others); a turn moves far more.
const SAME = 0.1;

const v = useViewer({ tmpPrefix: 'cgview-e2e-compare-', mesh: elephant });

async function run(algorithm) {
  await v.page.locator('#algorithm-menu').selectOption(algorithm);
  const form = v.page.locator(`form.algorithm-form[data-algorithm="${algorithm}"]`);
  await form.locator('button.run').click();
  const li = v.page.locator(`#jobs li.job[data-algorithm="${algorithm}"][data-state="done"]`).first();
  await li.waitFor({ timeout: 120000 }).catch((e) => {
    throw new Error(`${algorithm} never showed done: ${e.message}${v.describeProblems()}\n${v.server.log()}`);
  });
  const id = await li.getAttribute('data-job-id');
  // Its first field is drawn when it finishes.
  await v.page.waitForFunction((jobId) => window.__cgview.lastField?.jobId === jobId, id, { timeout: 60000 });
  const job = await (await fetch(`${v.server.url}/api/v1/jobs/${id}`)).json();
  return { li, job };
}

// The histogram of a legend: its bins and total, and the count of each bar.
async function histogramOf(legend) {
  const svg = legend.locator('svg.legend-histogram');
  const bins = Number(await svg.getAttribute('data-bins'));
  const total = Number(await svg.getAttribute('data-total'));
  const counts = await svg.locator('rect').evaluateAll((rs) => rs.map((r) => Number(r.dataset.count)));
  return { bins, total, counts };
}

function checkHistogram(h, count, what, filled = 3) {
  assert.ok(h.bins >= 32 && h.bins <= 64, `${what}: 32 to 64 bins: ${h.bins}`);
  assert.equal(h.counts.length, h.bins, `${what}: one bar per bin`);
  assert.equal(h.total, count, `${what}: every value is counted`);
  assert.equal(
    h.counts.reduce((a, b) => a + b, 0),
    count,
    `${what}: the bars add up to the values`,
  );
  assert.ok(h.counts.filter((n) => n > 0).length >= filled, `${what}: the values spread over ${filled} bins or more: ${h.counts}`);
}

// Waits until the viewer has stopped drawing (the orbit's damping settles): no new frame over a second.
async function settled() {
  await v.page.waitForFunction(
    () => {
      const same = window.__lastFrames === window.__cgview.frames;
      window.__lastFrames = window.__cgview.frames;
      return same;
    },
    null,
    { polling: 1000, timeout: 60000 },
  );
}

// The canvas without the overlays, cut into its panes (a row of n), each
// cropped to the same width, 2 pixels in from its cell's left edge.
async function panes(n, file) {
  const png = await v.page.locator('#viewport canvas').screenshot({
    path: path.join(artifacts, file),
    style: '.legend, .messages, .compare-options { visibility: hidden !important; }',
  });
  const img = await pngPixels(v.page, png);
  const width = Math.floor(img.width / n) - 4;
  return Array.from({ length: n }, (_, i) => {
    const x0 = Math.round((i * img.width) / n) + 2;
    const x1 = x0 + width;
    const data = new Uint8Array(width * img.height * 4);
    for (let y = 0; y < img.height; ++y) data.set(img.data.subarray((y * img.width + x0) * 4, (y * img.width + x1) * 4), y * width * 4);
    return { width, height: img.height, data };
  });
}

// Which pixels show the mesh (not the background), one byte per pixel.
function silhouette({ data }) {
  const mask = new Uint8Array(data.length / 4);
  for (let p = 0; p < mask.length; ++p) {
    const d = Math.abs(data[4 * p] - BACKGROUND[0]) + Math.abs(data[4 * p + 1] - BACKGROUND[1]) + Math.abs(data[4 * p + 2] - BACKGROUND[2]);
    mask[p] = d > 24 ? 1 : 0;
  }
  return mask;
}

// How far two silhouettes differ: the pixels in one only, over the pixels in either.
function apart(a, b) {
  let either = 0;
  let one = 0;
  for (let i = 0; i < a.length; ++i) {
    either += a[i] | b[i];
    one += a[i] ^ b[i];
  }
  return one / Math.max(1, either);
}

// The share of pixels where two images differ by more than `tolerance` (summed over the channels).
function differing(a, b, stride, tolerance) {
  let n = 0;
  for (let i = 0; i < a.length; i += stride) {
    let d = 0;
    for (let k = 0; k < stride; ++k) d += Math.abs(a[i + k] - b[i + k]);
    if (d > tolerance) ++n;
  }
  return n / (a.length / stride);
}

const greenShare = ({ buckets, saturated }) => (buckets[3] + buckets[4]) / Math.max(1, saturated); // hues 90°..150°

let distance = null;
let curvature = null;

test('a magnitude field is drawn on turbo, its legend with a histogram of every value', async () => {
  distance = await run('centroid_distance');
  const field = distance.job.artifacts.find((a) => a.kind === 'scalar_field');
  assert.equal(field.hint, 'magnitude');
  const shown = await v.page.evaluate(() => window.__cgview.lastField);
  assert.equal(shown.map, 'turbo', 'the magnitude hint chooses turbo');
  const legend = v.page.locator('#legend');
  assert.equal(await legend.getAttribute('data-map'), 'turbo');
  checkHistogram(await histogramOf(legend), shown.count, 'the distance');
  assert.deepEqual(v.problems, [], v.describeProblems());
});

test('"Compare" shows every field of the job side by side, "Add to comparison" adds one of another job', async () => {
  curvature = await run('curvature');
  const fields = curvature.job.artifacts.filter((a) => a.kind === 'scalar_field');
  assert.equal(fields.length, 2, `curvature gives two fields: ${JSON.stringify(curvature.job.artifacts)}`);
  await curvature.li.locator('button.compare').click();
  await v.page.waitForFunction(() => window.__cgview.lastCompare?.panes.length === 2, null, { timeout: 60000 });
  assert.ok(await v.page.locator('#leave-compare').isVisible(), 'the way back is offered');
  assert.ok(await v.page.locator('#legend').isHidden(), 'one legend per pane, not the single one');

  const row = v.page.locator(`#jobs li.job[data-job-id="${distance.job.id}"] .artifact-scalar_field`).first();
  await row.locator('button.compare-add').click();
  await v.page.waitForFunction(() => window.__cgview.lastCompare?.panes.length === 3, null, { timeout: 60000 });
  const compare = await v.page.evaluate(() => window.__cgview.lastCompare);
  assert.equal(compare.meshId, v.meshId);
  assert.deepEqual(
    compare.panes.map((p) => [p.jobId, p.artifact, p.map]),
    [...fields.map((f) => [curvature.job.id, f.name, 'coolwarm']), [distance.job.id, 'distance', 'turbo']],
    'each pane has its field and the map of its hint',
  );
  assert.equal(await row.locator('button.compare-add').innerText(), 'Compared');

  // Each pane has its legend: its title, its map, a histogram of all its values.
  const cells = v.page.locator('.compare-view .compare-pane');
  assert.equal(await cells.count(), 3);
  const counts = [...fields.map((f) => f.count), distance.job.artifacts.find((a) => a.kind === 'scalar_field').count];
  for (let i = 0; i < 3; ++i) {
    const legend = cells.nth(i).locator('.legend');
    assert.ok(await legend.isVisible(), `pane ${i} has a legend`);
    assert.equal(await legend.getAttribute('data-map'), compare.panes[i].map);
    assert.match(await legend.locator('.legend-title').innerText(), new RegExp(compare.panes[i].artifact));
    checkHistogram(await histogramOf(legend), counts[i], `pane ${i}`);
  }
  assert.deepEqual(v.problems, [], v.describeProblems());
});

test('each pane shows its own field; a drag in the first pane turns the one camera of all three', async (t) => {
  assert.ok(curvature && distance, 'the compare test ran');
  await settled();
  const before = await panes(3, 'e2e-compare-before.png');
  const masks = before.map(silhouette);
  const hues = before.map(hueStats);
  const drawn = masks.map((m) => m.reduce((a, b) => a + b, 0));
  const fieldsDiffer = differing(before[0].data, before[1].data, 4, 24);
  t.diagnostic(`mesh pixels ${drawn}; mean vs Gaussian curvature: ${fieldsDiffer}; hues ${hues.map((h) => JSON.stringify(h)).join(' ')}`);
  for (const [i, n] of drawn.entries()) assert.ok(n > 2000, `pane ${i} shows the mesh: ${n} pixels`);
  // turbo goes through green, coolwarm (blue, white, red: curvature is near 0 almost everywhere) never does.
  assert.ok(hues[2].saturated > 0.5 * drawn[2] && greenShare(hues[2]) > 0.05 && hues[2].distinct >= 3, `turbo in the third pane: ${JSON.stringify(hues[2])}`);
  for (const i of [0, 1]) assert.ok(greenShare(hues[i]) < 0.02, `coolwarm in pane ${i}: ${JSON.stringify(hues[i])}`);
  assert.ok(fieldsDiffer > 0.001, `mean and Gaussian curvature are drawn differently: ${fieldsDiffer}`);
  // One camera: the same silhouette in every pane.
  const same = [1, 2].map((i) => apart(masks[0], masks[i]));
  t.diagnostic(`silhouettes apart from pane 0's: ${same}`);
  for (const [k, d] of same.entries()) assert.ok(d < SAME, `pane ${k + 1} has the silhouette of pane 0: ${d}`);

  const box = await v.page.locator('#viewport canvas').boundingBox();
  const x = box.x + box.width / 6;
  const y = box.y + box.height / 2;
  await v.page.mouse.move(x, y);
  await v.page.mouse.down();
  await v.page.mouse.move(x + box.width / 8, y + 20, { steps: 8 });
  await v.page.mouse.up();
  await settled();
  const after = await panes(3, 'e2e-compare-after.png');
  const turned = after.map(silhouette);
  for (let i = 0; i < 3; ++i) {
    const moved = apart(masks[i], turned[i]);
    const still = apart(turned[0], turned[i]);
    t.diagnostic(`pane ${i}: moved ${moved}, apart from pane 0 ${still}`);
    assert.ok(moved > 3 * SAME, `pane ${i} turned with the drag in pane 0: ${moved}`);
    assert.ok(still < SAME, `pane ${i} still has the silhouette of pane 0: ${still}`);
  }
  assert.deepEqual(v.problems, [], v.describeProblems());
});

test('"One range per hint" colours the two curvatures over one range; the distance keeps its own', async () => {
  const ranges = () => v.page.evaluate(() => window.__cgview.lastCompare.panes.map((p) => p.range));
  const own = await ranges();
  assert.notDeepEqual(own[0], own[1], 'mean and Gaussian curvature have ranges of their own');
  const box = v.page.locator('.compare-view input.compare-same-range');
  await box.check();
  await v.page.waitForFunction((r) => JSON.stringify(window.__cgview.lastCompare.panes.map((p) => p.range)) !== r, JSON.stringify(own), { timeout: 10000 });
  const shared = await ranges();
  const hi = Math.max(own[0][1], own[1][1]);
  assert.deepEqual(
    shared.slice(0, 2),
    [
      [-hi, hi],
      [-hi, hi],
    ],
    'both symmetric fields over their common range',
  );
  assert.deepEqual(shared[2], own[2], 'the only magnitude field keeps its range');
  const legends = v.page.locator('.compare-view .compare-pane .legend');
  assert.equal(await legends.nth(0).locator('.legend-max').innerText(), await legends.nth(1).locator('.legend-max').innerText());
  // The histogram follows the range: still every value, in fewer, wider-spaced bins.
  const count = curvature.job.artifacts.find((a) => a.name === 'mean_curvature').count;
  checkHistogram(await histogramOf(legends.nth(0)), count, 'mean curvature over the common range', 1);
  await box.uncheck();
  await v.page.waitForFunction((r) => JSON.stringify(window.__cgview.lastCompare.panes.map((p) => p.range)) === r, JSON.stringify(own), { timeout: 10000 });
  assert.deepEqual(v.problems, [], v.describeProblems());
});

test('"Leave comparison" goes back to one view with the field shown before', async () => {
  await v.page.locator('#leave-compare').click();
  await v.page.waitForFunction(() => window.__cgview.lastCompare === null && !document.querySelector('.compare-view'), null, { timeout: 10000 });
  assert.ok(await v.page.locator('#leave-compare').isHidden());
  const legend = v.page.locator('#legend');
  assert.ok(await legend.isVisible(), 'the single legend is back');
  assert.match(await legend.locator('.legend-title').innerText(), /mean_curvature/);
  await settled();
  const [whole] = await panes(1, 'e2e-compare-left.png');
  const drawn = silhouette(whole).reduce((a, b) => a + b, 0);
  assert.ok(drawn > 20000, `the mesh fills the whole view again, larger than in a pane: ${drawn} pixels`);
  assert.deepEqual(v.problems, [], v.describeProblems());
});

// The SDF comparison view of the paper's Figure 9: sdf_fast with compare on
// gives the full SDF, its approximation from 10% of the faces and the error
// map; one "Compare" shows the three side by side, per face, the error on turbo.
test('sdf_fast with compare: the full SDF, the approximation and the error map side by side', async () => {
  await v.page.locator('#algorithm-menu').selectOption('sdf_fast');
  const form = v.page.locator('form.algorithm-form[data-algorithm="sdf_fast"]');
  await form.locator('input[data-param="compare"]').check();
  await form.locator('button.run').click();
  const li = v.page.locator('#jobs li.job[data-algorithm="sdf_fast"][data-state="done"]').first();
  await li.waitFor({ timeout: 120000 });
  const job = await (await fetch(`${v.server.url}/api/v1/jobs/${await li.getAttribute('data-job-id')}`)).json();
  assert.equal(job.params.compare, true, JSON.stringify(job.params));
  const fields = job.artifacts.filter((a) => a.kind === 'scalar_field').map((a) => a.name);
  assert.deepEqual(fields.sort(), ['error', 'sdf', 'sdf_fast']);
  await li.locator('button.compare').click();
  await v.page.waitForFunction(() => window.__cgview.lastCompare?.panes.length === 3, null, { timeout: 60000 });
  const compare = await v.page.evaluate(() => window.__cgview.lastCompare);
  const byName = Object.fromEntries(compare.panes.map((p) => [p.artifact, p.map]));
  assert.equal(byName.error, 'turbo', `the error map is blue for none, towards red for the most: ${JSON.stringify(compare)}`);
  const cells = v.page.locator('.compare-view .compare-pane');
  const faces = job.artifacts.find((a) => a.name === 'sdf').count;
  for (let i = 0; i < 3; ++i) checkHistogram(await histogramOf(cells.nth(i).locator('.legend')), faces, `pane ${i}`);
  await settled();
  await v.page.locator('#viewport canvas').screenshot({ path: path.join(artifacts, 'e2e-compare-sdf.png') });
  await v.page.locator('#leave-compare').click();
  assert.deepEqual(v.problems, [], v.describeProblems());
});
