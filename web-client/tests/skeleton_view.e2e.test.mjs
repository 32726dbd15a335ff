// End-to-end test of how skeletons are drawn and compared, against the real
// server and Debian's chromium:
//   CGVIEW_SERVER=build/bin/cgview-server node --test tests/skeleton_view.e2e.test.mjs
//
// A closed box 4 × 1 × 1 (faces subdivided, so that its wireframe is dense)
// and two skeleton files inside it, loaded with "Load skeleton file…". The
// comparison table fits the sidebar with every skeleton's column in view;
// over the wireframe each skeleton is a line several pixels wide; "X-ray"
// shows them, with a sphere at each end, through the opaque surface, and
// off, the surface hides them; side by side, the panes draw the surface in
// the display mode chosen (wireframe: fewer pixels than the shaded surface).
//
// Environment: CGVIEW_SERVER (default build/bin/cgview-server), CHROMIUM.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { artifactsDir, isMeshOrange, pngPixels, settle, useViewer } from './harness.mjs';

const dir = fs.mkdtempSync(path.join(os.tmpdir(), 'cgview-skeleton-view-'));
process.on('exit', () => fs.rmSync(dir, { recursive: true, force: true }));

/** A closed box [-a, a] × [-b, b] × [-c, c] with its faces cut into a grid of n[0] × n[1] × n[2] cells, as OFF text. */
function box([a, b, c], n) {
  const ids = new Map();
  const vertices = [];
  const at = (i, j, k) => {
    const key = `${i},${j},${k}`;
    if (!ids.has(key)) {
      ids.set(key, vertices.length);
      vertices.push([-a + (2 * a * i) / n[0], -b + (2 * b * j) / n[1], -c + (2 * c * k) / n[2]]);
    }
    return ids.get(key);
  };
  const faces = [];
  // Each side: the grid of its two free axes at one end of the third, turned to face out.
  for (let axis = 0; axis < 3; ++axis) {
    const [u, w] = [0, 1, 2].filter((k) => k !== axis);
    for (const end of [0, n[axis]]) {
      for (let p = 0; p < n[u]; ++p) {
        for (let q = 0; q < n[w]; ++q) {
          const corner = (dp, dq) => {
            const ijk = [0, 0, 0];
            ijk[axis] = end;
            ijk[u] = p + dp;
            ijk[w] = q + dq;
            return at(...ijk);
          };
          const quad = [corner(0, 0), corner(1, 0), corner(1, 1), corner(0, 1)];
          // (u, w, axis) is right-handed for axis 0 and 2, not for 1.
          const out = (end === 0) === (axis !== 1);
          faces.push(out ? quad.reverse() : quad);
        }
      }
    }
  }
  return `OFF\n${vertices.length} ${faces.length} 0\n${vertices.map((p) => p.join(' ')).join('\n')}\n${faces.map((f) => `4 ${f.join(' ')}`).join('\n')}\n`;
}

/** A skeleton as .cg text (1-based): a polyline through `points`, and optionally a branch from its middle node. */
function cg(points, branch = []) {
  const nodes = [...points, ...branch];
  const edges = points.slice(1).map((_, i) => [i + 1, i + 2]);
  const middle = Math.ceil(points.length / 2);
  branch.forEach((_, i) => edges.push([i === 0 ? middle : points.length + i, points.length + i + 1]));
  return [`# D:3 NV:${nodes.length} NE:${edges.length}`, ...nodes.map((p) => `v ${p.join(' ')}`), ...edges.map(([x, y]) => `e ${x} ${y}`)].join('\n') + '\n';
}

const along = (y, z) => Array.from({ length: 10 }, (_, i) => [-1.8 + 0.4 * i, y, z]);
const files = {
  'spine_tool_a.cg': cg(along(0, 0)),
  'spine_tool_b.cg': cg(along(0.15, 0.1), [
    [0.2, 0.3, 0.2],
    [0.3, 0.4, 0.3],
  ]),
};
const meshFile = path.join(dir, 'bar.off');
fs.writeFileSync(meshFile, box([2, 0.5, 0.5], [16, 4, 4]));
for (const [name, text] of Object.entries(files)) fs.writeFileSync(path.join(dir, name), text);

const v = useViewer({ tmpPrefix: 'cgview-skeleton-view-', mesh: meshFile });

async function canvas(name) {
  await settle(v.page);
  const png = await v.page.locator('#viewport canvas').screenshot();
  fs.writeFileSync(path.join(artifactsDir, `e2e-skeleton-view-${name}.png`), png);
  return pngPixels(v.page, png);
}

/** Whether a pixel is within `tolerance` (sum over channels) of an sRGB colour. */
function near(img, i, hex, tolerance = 40) {
  const n = parseInt(hex.slice(1), 16);
  return Math.abs(img.data[i] - ((n >> 16) & 255)) + Math.abs(img.data[i + 1] - ((n >> 8) & 255)) + Math.abs(img.data[i + 2] - (n & 255)) < tolerance;
}

function countColour(img, hex, x0 = 0, x1 = 1) {
  let count = 0;
  for (let y = 0; y < img.height; ++y) for (let x = Math.floor(x0 * img.width); x < Math.floor(x1 * img.width); ++x) if (near(img, (y * img.width + x) * 4, hex)) ++count;
  return count;
}

/** The median, over the columns that hold a colour, of how many pixels of it each holds: a line's width for a line closer to horizontal than vertical. */
function columnWidth(img, hex) {
  const counts = [];
  for (let x = 0; x < img.width; ++x) {
    let n = 0;
    for (let y = 0; y < img.height; ++y) if (near(img, (y * img.width + x) * 4, hex)) ++n;
    if (n) counts.push(n);
  }
  counts.sort((a, b) => a - b);
  return counts.length ? counts[counts.length >> 1] : 0;
}

/** Where the page's camera draws world point `p`, in CSS pixels of the canvas. */
async function project(p) {
  const { width, height, viewProjection: m } = await v.page.evaluate(() => window.__cgview.selectionView());
  const w = m[3] * p[0] + m[7] * p[1] + m[11] * p[2] + m[15];
  const x = (m[0] * p[0] + m[4] * p[1] + m[8] * p[2] + m[12]) / w;
  const y = (m[1] * p[0] + m[5] * p[1] + m[9] * p[2] + m[13]) / w;
  return [((x + 1) / 2) * width, ((1 - y) / 2) * height];
}

const mode = async (value) => {
  await v.page.getByRole('combobox', { name: 'Display mode' }).selectOption(value);
  await v.page.waitForFunction((m) => window.__cgview.display?.mode === m, value);
};

let drawn = [];

test('skeleton files are drawn, and the comparison table keeps every column in the sidebar', async () => {
  const { page } = v;
  for (const name of Object.keys(files)) {
    const before = await page.evaluate(() => window.__cgview.skeletons.length);
    const [chooser] = await Promise.all([page.waitForEvent('filechooser'), page.getByRole('button', { name: 'Load skeleton file…' }).click()]);
    await chooser.setFiles(path.join(dir, name));
    await page.waitForFunction((n) => window.__cgview.skeletons.length === n, before + 1, { timeout: 60000 });
  }
  drawn = await page.evaluate(() => window.__cgview.skeletons);
  assert.equal(drawn.length, 2);
  const table = page.locator('#skeletons table.skeleton-table');
  await table.locator('th[data-skeleton]').nth(1).waitFor();
  const sidebar = page.locator('aside.sidebar.right');
  await sidebar.evaluate((s) => s.querySelector('#skeletons').scrollIntoView());
  const fits = await sidebar.evaluate((s) => {
    const panel = s.querySelector('#skeletons').getBoundingClientRect();
    const cells = [...s.querySelectorAll('#skeletons table.skeleton-table tr > *')].map((c) => c.getBoundingClientRect());
    return { overflow: s.scrollWidth - s.clientWidth, right: panel.right, cells: Math.max(...cells.map((r) => r.right)) };
  });
  assert.ok(fits.overflow <= 0, `the sidebar does not scroll sideways: ${JSON.stringify(fits)}`);
  assert.ok(fits.cells <= fits.right + 0.5, `every column of the table lies inside the panel: ${JSON.stringify(fits)}`);
  for (let i = 0; i < 2; ++i) assert.ok(await table.locator('th[data-skeleton]').nth(i).isVisible(), `skeleton ${i}'s column is shown`);
  assert.deepEqual(v.problems, [], v.describeProblems());
});

test('over a wireframe, each skeleton is a line several pixels wide', async () => {
  await mode('wireframe');
  const img = await canvas('wireframe');
  for (const s of drawn) {
    const width = columnWidth(img, s.color);
    assert.ok(width >= 2, `${s.key} is drawn ${width} pixel(s) wide in ${s.color}`);
  }
  assert.deepEqual(v.problems, [], v.describeProblems());
});

test('"X-ray" shows the skeletons, spheres at their nodes, through the opaque surface; off, the surface hides them', async () => {
  await mode('smooth');
  const xray = await canvas('smooth-xray');
  for (const s of drawn) assert.ok(countColour(xray, s.color) > 200, `${s.key} shows through the surface: ${countColour(xray, s.color)} pixels`);
  await v.page.getByRole('checkbox', { name: 'X-ray' }).uncheck();
  const hidden = await canvas('smooth-no-xray');
  for (const s of drawn) assert.ok(countColour(hidden, s.color) < 20, `${s.key} is hidden inside the box: ${countColour(hidden, s.color)} pixels`);

  // The first skeleton's end at x = 1.8: a sphere covers the pixels around it on every side; a line's end, or a dot, would leave some.
  const [x, y] = await project([1.8, 0, 0]);
  let changed = 0;
  let all = 0;
  for (let dy = -3; dy <= 3; ++dy) {
    for (let dx = -3; dx <= 3; ++dx) {
      const i = ((Math.round(y) + dy) * xray.width + Math.round(x) + dx) * 4;
      ++all;
      if (Math.abs(xray.data[i] - hidden.data[i]) + Math.abs(xray.data[i + 1] - hidden.data[i + 1]) + Math.abs(xray.data[i + 2] - hidden.data[i + 2]) > 30) ++changed;
    }
  }
  assert.ok(changed / all >= 0.9, `the end node at (${x.toFixed(0)}, ${y.toFixed(0)}) is a sphere: ${changed} of ${all} pixels around it are drawn`);

  await mode('wireframe');
  const wire = await canvas('wireframe-no-xray');
  for (const s of drawn) assert.ok(countColour(wire, s.color) > 100, `${s.key} is seen through the wireframe: ${countColour(wire, s.color)} pixels`);
  await v.page.getByRole('checkbox', { name: 'X-ray' }).check();
  await mode('smooth');
  assert.deepEqual(v.problems, [], v.describeProblems());
});

test('side by side, the panes draw the surface in the display mode', async () => {
  const { page } = v;
  await page.locator('#skeletons').getByRole('button', { name: 'Side by side', exact: true }).click();
  await page.waitForFunction(() => window.__cgview.lastCompare?.panes.length === 2, null, { timeout: 30000 });
  const orange = (img, x0, x1) => {
    let n = 0;
    for (let y = 0; y < img.height; ++y) {
      for (let x = Math.floor(x0 * img.width); x < Math.floor(x1 * img.width); ++x) {
        const i = (y * img.width + x) * 4;
        if (isMeshOrange(img.data[i], img.data[i + 1], img.data[i + 2])) ++n;
      }
    }
    return n;
  };
  const shaded = await canvas('side-smooth');
  await mode('wireframe');
  const wire = await canvas('side-wireframe');
  for (const [i, [x0, x1]] of [
    [0, 0.5],
    [0.5, 1],
  ].entries()) {
    const s = orange(shaded, x0, x1);
    const w = orange(wire, x0, x1);
    assert.ok(s > 2000, `pane ${i} shows the shaded surface: ${s} pixels`);
    assert.ok(w > 0 && w < 0.8 * s, `pane ${i} draws the surface as a wireframe: ${w} orange pixels, ${s} shaded`);
    assert.ok(countColour(wire, drawn[i].color, x0, x1) > 100, `pane ${i} shows its skeleton`);
  }
  await mode('smooth');
  await page.getByRole('button', { name: 'Leave comparison', exact: true }).click();
  await page.waitForFunction(() => window.__cgview.lastCompare === null && !document.querySelector('.compare-view'), null, { timeout: 10000 });
  assert.deepEqual(v.problems, [], v.describeProblems());
});
