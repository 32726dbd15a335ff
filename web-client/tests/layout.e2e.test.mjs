// End-to-end test of the page's layout, against the real server and Debian's
// chromium, at 1280 × 800 and at 1920 × 1080:
//   CGVIEW_SERVER=build/bin/cgview-server CGVIEW_SAMPLES=build/samples node --test tests/layout.e2e.test.mjs
//
// With the panels full (a mesh with a long name in the list, a curvature
// field shown with its legend, metrics tables in the job list, a voxel
// grid's slices open), measured from the DOM: nothing sticks out of its
// panel or makes a panel scroll sideways, no text spills out of its box, the
// toolbar is one row (every button at the same top), the Display panel is
// within the first screen, and every mesh name cut short has the whole name
// as its tooltip; comparing two fields (a wider toolbar, a legend per pane)
// keeps all that at 1280 × 800. A screenshot of each is kept in a
// temporary directory for looking at, not compared.
//
// Environment: CGVIEW_SERVER, CGVIEW_SAMPLES, CHROMIUM.
import { after, test } from 'node:test';
import assert from 'node:assert/strict';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { doneRow, repo, settle, submitJob, useViewer } from './harness.mjs';

const samples = process.env.CGVIEW_SAMPLES ?? path.join(repo, 'build', 'samples');
const v = useViewer({ tmpPrefix: 'cgview-layout-', mesh: path.join(samples, 'elephant.off') });
const shots = fs.mkdtempSync(path.join(os.tmpdir(), 'cgview-layout-shots-'));
after(() => console.log(`# layout screenshots: ${shots}`));

const LONG_NAME = 'an_elephant_with_a_name_far_too_long_for_the_mesh_list.off';

/**
 * Measured in the page: what sticks out of its panel (the sidebars, each
 * panel in them, the legend over the view, the toolbar), text that spills
 * out of its own box, the toolbar's buttons, the mesh names cut short.
 */
function measure() {
  const shown = (e) => e.getClientRects().length > 0 && getComputedStyle(e).visibility !== 'hidden';
  const name = (e) => {
    const id = e.id ? `#${e.id}` : '';
    const cls = typeof e.className === 'string' && e.className ? `.${e.className.trim().split(/\s+/).join('.')}` : '';
    const text = (e.textContent ?? '').trim().replace(/\s+/g, ' ').slice(0, 40);
    return `${e.tagName.toLowerCase()}${id}${cls}${text ? ` "${text}"` : ''}`;
  };
  const out = [];
  const panels = [...document.querySelectorAll('.topbar, .sidebar, .sidebar .panel, .legend')].filter(shown);
  for (const panel of panels) {
    const p = panel.getBoundingClientRect();
    if (panel.scrollWidth > panel.clientWidth + 1) out.push(`${name(panel)} scrolls sideways: ${panel.scrollWidth} > ${panel.clientWidth}`);
    for (const e of panel.querySelectorAll('*')) {
      if (!shown(e)) continue;
      const r = e.getBoundingClientRect();
      if (r.width === 0 || r.height === 0) continue;
      if (r.right > p.right + 1) out.push(`${name(e)} ends at x ${Math.round(r.right)}, past ${name(panel).slice(0, 40)} at ${Math.round(p.right)}`);
      if (r.left < p.left - 1) out.push(`${name(e)} starts at x ${Math.round(r.left)}, before ${name(panel).slice(0, 40)} at ${Math.round(p.left)}`);
    }
  }
  // Text spilling out of a box that neither clips nor scrolls it (controls scroll their own text; SVG has no text box).
  const skip = new Set(['INPUT', 'SELECT', 'TEXTAREA', 'CANVAS', 'OPTION', 'IMG']);
  for (const panel of panels) {
    for (const e of panel.querySelectorAll('*')) {
      if (skip.has(e.tagName) || e instanceof SVGElement || !shown(e)) continue;
      const s = getComputedStyle(e);
      if (s.display === 'inline' || s.overflowX !== 'visible' || e.clientWidth === 0) continue;
      if (e.scrollWidth > e.clientWidth + 1) out.push(`${name(e)} spills out of its box: ${e.scrollWidth} > ${e.clientWidth}`);
    }
  }
  const bar = document.querySelector('.topbar');
  const buttons = [...bar.querySelectorAll('button, .button, select')].filter(shown).map((b) => {
    const r = b.getBoundingClientRect();
    return { text: (b.textContent ?? '').trim().slice(0, 20), top: r.top, bottom: r.bottom, right: r.right };
  });
  const names = [...document.querySelectorAll('#mesh-list .mesh-name')].filter(shown).map((e) => ({
    text: e.textContent,
    title: e.title,
    cut: e.scrollWidth > e.clientWidth + 1,
  }));
  const display = document.querySelector('#display').getBoundingClientRect();
  return { overflows: out, buttons, bar: bar.getBoundingClientRect().bottom, names, displayTop: display.top, width: innerWidth, height: innerHeight };
}

test('the panels filled: a long mesh name, a field and its legend, metrics tables, voxel slices', async () => {
  const { page } = v;
  const r = await fetch(`${v.server.url}/api/v1/meshes?name=${encodeURIComponent(LONG_NAME)}`, {
    method: 'POST',
    body: fs.readFileSync(path.join(samples, 'elephant.off')),
  });
  assert.equal(r.status, 201, await r.clone().text());
  await page.locator('#mesh-list .mesh-name', { hasText: LONG_NAME }).waitFor();

  const curvature = (curvatureJob = await submitJob(v, 'curvature', { mesh: v.meshId }));
  const orient = await submitJob(v, 'orient_outward', { mesh: v.meshId });
  const voxels = await submitJob(v, 'voxel_distance', { mesh: v.meshId }, { resolution: 24 });
  // Long metric names with long units beside them, in the narrow left sidebar.
  const embed = await submitJob(v, 'chaos_embed', { mesh: v.meshId }, { key: 'k', message: 'layout' });
  await (await doneRow(v, orient)).getByRole('table').waitFor({ timeout: 20000 });
  await (await doneRow(v, embed)).getByRole('table').waitFor({ timeout: 20000 });
  await (await doneRow(v, voxels)).getByRole('button', { name: 'Slices' }).click();
  await page.locator('#voxel-slices').getByRole('group', { name: 'Slice legend' }).waitFor({ state: 'visible', timeout: 30000 });
  await (await doneRow(v, curvature)).locator('.artifact[data-artifact="mean_curvature"]').getByRole('button', { name: 'Show' }).click();
  await page.locator('#legend').waitFor({ state: 'visible', timeout: 30000 });
  assert.deepEqual(v.problems, [], v.describeProblems());
});

/** Asserts, at the page's size now, that nothing sticks out and the toolbar is one row; returns the measures. */
async function checkLayout(width, height, what) {
  const { page } = v;
  await settle(page);
  await page.screenshot({ path: path.join(shots, `layout-${what}-${width}x${height}.png`) });
  const m = await page.evaluate(measure);
  assert.equal(m.width, width);
  assert.deepEqual(m.overflows, [], `what sticks out at ${width} × ${height} (${what}):\n${m.overflows.join('\n')}`);
  const tops = m.buttons.map((b) => b.top);
  assert.ok(m.buttons.length >= 10, `the toolbar's buttons: ${JSON.stringify(m.buttons)}`);
  assert.ok(Math.max(...tops) - Math.min(...tops) <= 1, `one row: every toolbar button at the same top: ${JSON.stringify(m.buttons)}`);
  for (const b of m.buttons) assert.ok(b.bottom <= m.bar + 1 && b.right <= width, `"${b.text}" within the toolbar: ${JSON.stringify(b)}`);
  return m;
}

let curvatureJob = null;

for (const [width, height] of [
  [1280, 800],
  [1920, 1080],
]) {
  test(`at ${width} × ${height}: nothing sticks out of its panel, the toolbar is one row, cut mesh names have tooltips`, async () => {
    await v.page.setViewportSize({ width, height });
    const m = await checkLayout(width, height, 'panels');
    assert.ok(m.displayTop < height * 0.5, `the Display panel starts in the upper half of the page: at ${m.displayTop}`);
    const long = m.names.find((n) => n.text === LONG_NAME);
    assert.ok(long?.cut, `the long name is cut in the list: ${JSON.stringify(m.names)}`);
    for (const n of m.names.filter((x) => x.cut)) assert.equal(n.title, n.text, `a cut mesh name has the whole name as its tooltip: ${JSON.stringify(n)}`);
    assert.deepEqual(v.problems, [], v.describeProblems());
  });
}

test('comparing two fields at 1280 × 800: "Leave comparison" joins the toolbar, still one row; the panes\' legends fit', async () => {
  const { page } = v;
  await page.setViewportSize({ width: 1280, height: 800 });
  await page.locator(`#jobs li.job[data-job-id="${curvatureJob}"]`).getByRole('button', { name: 'Compare' }).click();
  const leave = page.getByRole('button', { name: 'Leave comparison' });
  await leave.waitFor({ state: 'visible', timeout: 30000 });
  await page.locator('.compare-pane .legend').first().waitFor({ state: 'visible', timeout: 30000 });
  await checkLayout(1280, 800, 'compare');
  await leave.click();
  await leave.waitFor({ state: 'hidden' });
  assert.deepEqual(v.problems, [], v.describeProblems());
});
