// End-to-end test of what the viewer's numbers say they are, against the real
// server and Debian's chromium:
//   CGVIEW_SERVER=build/bin/cgview-server CGVIEW_SAMPLES=build/samples node --test tests/units.e2e.test.mjs
//
// On the elephant: the report gives its box, area and volume in mesh units
// and its counts bare; a chaos_embed job's metrics table gives its relative
// displacements in per cent of the diagonal and its signal-to-noise ratio in
// dB; a curvature field shown has a legend saying what the values are and
// their unit, its min and max to four significant digits; a voxel_distance
// grid's slice has a legend of its own; and the slice and threshold sliders
// show their values beside them, which follow them when they move.
//
// Jobs are submitted over REST (as another client would); everything else
// goes through what a user sees: rows by their headers, buttons and sliders
// by their names.
//
// Environment: CGVIEW_SERVER, CGVIEW_SAMPLES, CHROMIUM.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import path from 'node:path';
import { doneRow, repo, shortNumber, submitJob, useViewer } from './harness.mjs';

const samples = process.env.CGVIEW_SAMPLES ?? path.join(repo, 'build', 'samples');
const v = useViewer({ tmpPrefix: 'cgview-units-', mesh: path.join(samples, 'elephant.off') });

/** The value cell of the row headed `name` in `table`. */
function cellOf(table, name) {
  return table
    .getByRole('row')
    .filter({ has: v.page.getByRole('rowheader', { name, exact: true }) })
    .getByRole('cell');
}

test('the report gives the box, the area and the volume in mesh units, and its counts bare', async () => {
  const report = v.page.locator('#report');
  await report.getByRole('heading', { name: 'elephant.off' }).waitFor();
  assert.equal(await cellOf(report, 'vertices').innerText(), '2775');
  assert.equal(await cellOf(report, 'faces').innerText(), '5558');
  const area = await cellOf(report, 'area').innerText();
  assert.match(area, /^[0-9.]+ mesh units²$/, `area: ${area}`);
  shortNumber(area.split(' ')[0], 'the area');
  const volume = await cellOf(report, 'volume').innerText();
  assert.match(volume, /^[0-9.]+ mesh units³$/, `volume: ${volume}`);
  assert.match(await cellOf(report, 'bbox min').innerText(), /^\(-?[0-9.]+, -?[0-9.]+, -?[0-9.]+\) mesh units$/);
  const diagonal = await cellOf(report, 'bbox diagonal').innerText();
  assert.match(diagonal, /^[0-9.]+ mesh units$/, `bbox diagonal: ${diagonal}`);
  // The elephant's box is 0.7204 × 1 × 0.6030.
  assert.ok(Math.abs(shortNumber(diagonal.split(' ')[0], 'the diagonal') - Math.hypot(0.7204, 1, 0.603)) < 2e-3, diagonal);
  assert.deepEqual(v.problems, [], v.describeProblems());
});

test("a job's metrics table gives relative values in % of the diagonal, the SNR in dB, sizes in bytes", async () => {
  const jobId = await submitJob(v, 'chaos_embed', { mesh: v.meshId }, { key: 'k', message: 'units and legends' });
  const li = await doneRow(v, jobId);
  const table = li.getByRole('table');
  await table.waitFor({ timeout: 20000 });
  const metrics = await (await fetch(`${v.server.url}/api/v1/jobs/${jobId}/artifacts/metrics?format=json`)).json();

  const rms = cellOf(table, 'rms relative');
  const text = await rms.innerText();
  const m = /^(\S+) % of diagonal$/.exec(text);
  assert.ok(m, `rms relative: "${text}"`);
  const shown = shortNumber(m[1], 'rms relative');
  assert.ok(Math.abs(shown - 100 * metrics.rms_relative) <= 5e-4 * 100 * metrics.rms_relative, `${shown} % is ${metrics.rms_relative} of the diagonal`);
  // Its tooltip says what it is relative to, with the value as sent.
  const title = await rms.getAttribute('title');
  assert.match(title, /diagonal/);
  assert.ok(title.startsWith(String(metrics.rms_relative)), title);

  assert.match(await cellOf(table, 'snr db').innerText(), /^-?[0-9.]+ dB$/);
  assert.equal(await cellOf(table, 'message bytes').innerText(), `${metrics.message_bytes} bytes`, 'a count stays exact');
  assert.equal(await cellOf(table, 'bits per coordinate').innerText(), `${metrics.bits_per_coordinate} bits`);
  assert.deepEqual(v.problems, [], v.describeProblems());
});

test('a curvature field shown has a legend: what the values are, their unit, min and max to 4 significant digits', async () => {
  const jobId = await submitJob(v, 'curvature', { mesh: v.meshId });
  const li = await doneRow(v, jobId);
  for (const [artifact, unit] of [
    ['mean_curvature', 'mesh units⁻¹'],
    ['gaussian_curvature', 'mesh units⁻²'],
  ]) {
    await li.locator(`.artifact[data-artifact="${artifact}"]`).getByRole('button', { name: 'Show' }).click();
    await v.page.waitForFunction(
      ({ id, name }) => window.__cgview.lastField?.jobId === id && window.__cgview.lastField.artifact === name,
      { id: jobId, name: artifact },
      { timeout: 30000 },
    );
    const legend = v.page.locator('#legend');
    await legend.waitFor({ state: 'visible' });
    const title = await legend.locator('.legend-title').innerText();
    assert.ok(title.replace(/\s+/g, ' ').includes(`curvature · ${artifact} (${unit})`), `the legend's title: ${title}`);
    const range = await v.page.evaluate(() => window.__cgview.lastField.range);
    const lo = shortNumber(await legend.locator('.legend-min').innerText(), 'the legend min');
    const hi = shortNumber(await legend.locator('.legend-max').innerText(), 'the legend max');
    const tolerance = 5e-4 * Math.max(Math.abs(range[0]), Math.abs(range[1]));
    assert.ok(Math.abs(lo - range[0]) <= tolerance && Math.abs(hi - range[1]) <= tolerance, `legend ${lo} … ${hi}, field ${range}`);
  }
  assert.deepEqual(v.problems, [], v.describeProblems());
});

test('a voxel slice has a legend with its unit and range; the sliders show their values, which follow them', async () => {
  const jobId = await submitJob(v, 'voxel_distance', { mesh: v.meshId }, { resolution: 24 });
  const li = await doneRow(v, jobId);
  await li.getByRole('button', { name: 'Slices' }).click();
  const panel = v.page.locator('#voxel-slices');
  await panel.waitFor({ state: 'visible' });
  const slice = panel.getByRole('slider', { name: 'Slice index' });
  const sliceValue = panel.locator('label', { has: v.page.getByRole('slider', { name: 'Slice index' }) }).locator('.slice-label');
  // The first answer sets the slider's range, then the middle slice is fetched.
  await v.page.waitForFunction(
    () => {
      const m = /^(\d+) \/ (\d+)$/.exec(document.querySelector('#voxel-slices .slice-label')?.textContent ?? '');
      return m !== null && Number(m[1]) === Math.floor((Number(m[2]) + 1) / 2) && Number(m[1]) > 0;
    },
    null,
    { timeout: 30000 },
  );
  const middle = (await sliceValue.innerText()).split(' ')[0];
  assert.equal(await slice.inputValue(), middle, 'the value beside the slider is its own');
  const legend = panel.getByRole('group', { name: 'Slice legend' });
  await legend.waitFor({ state: 'visible' });
  assert.match(await legend.innerText(), /distance \(mesh units\)/);
  const lo = shortNumber(await legend.locator('.slice-legend-min').innerText(), 'the slice min');
  const hi = shortNumber(await legend.locator('.slice-legend-max').innerText(), 'the slice max');
  assert.ok(lo >= 0 && hi > lo && hi < 0.5, `distances inside the elephant (at most half its 1-unit height): ${lo} … ${hi}`);

  // The slice slider: its value beside it, following it.
  const before = await sliceValue.innerText();
  await slice.fill('3');
  await v.page.waitForFunction(() => document.querySelector('#voxel-slices .slice-label')?.textContent?.startsWith('3 / '), null, { timeout: 15000 });
  assert.notEqual(await sliceValue.innerText(), before);
  await slice.fill(middle);
  await v.page.waitForFunction((m) => document.querySelector('#voxel-slices .slice-label')?.textContent?.startsWith(`${m} / `), middle, { timeout: 15000 });

  // The threshold slider: off at 0, then the share of the range and the value it cuts at, in the grid's unit.
  const threshold = panel.getByRole('slider', { name: 'Threshold' });
  const thresholdValue = panel.locator('label', { has: v.page.getByRole('slider', { name: 'Threshold' }) }).locator('.threshold-label');
  assert.equal(await thresholdValue.innerText(), 'off');
  await threshold.fill('500');
  await v.page.waitForFunction(() => document.querySelector('#voxel-slices .threshold-label')?.textContent !== 'off');
  const half = /^50\s% \(≥ (\S+) mesh units\)$/.exec(await thresholdValue.innerText());
  assert.ok(half, `the threshold's value: ${await thresholdValue.innerText()}`);
  const [loMiddle, hiMiddle] = [Number(await legend.locator('.slice-legend-min').innerText()), Number(await legend.locator('.slice-legend-max').innerText())];
  const cut = shortNumber(half[1], 'the threshold');
  assert.ok(Math.abs(cut - (loMiddle + hiMiddle) / 2) <= 1e-3 * Math.max(1e-9, hiMiddle), `half way through ${loMiddle} … ${hiMiddle}: ${cut}`);
  assert.equal(await legend.locator('.slice-legend-cut').innerText(), `≥ ${half[1]}`, 'the legend marks the threshold');
  await threshold.fill('250');
  await v.page.waitForFunction(() => /^25\s%/.test(document.querySelector('#voxel-slices .threshold-label')?.textContent ?? ''));
  assert.deepEqual(v.problems, [], v.describeProblems());
});
