// End-to-end test of the selection and the navigation, against the real
// server in chromium: a flat grid whose faces and vertices the file lists in
// a shuffled order (so that ids from the Draco stream, which Edgebreaker
// reorders, could not pass for the stored ones) is seen from the front; a
// box and a lasso select exactly the faces whose centroids this test
// projects into them with the page's camera matrices (the ids compared, not
// only the count); grow and shrink match a brute-force ring; extract_faces
// runs on the selection from the form and its output has exactly those
// faces; an id out of range is a 400 naming it. Then the axis views, the
// keys and fly mode move the camera as they should.
//
// Environment: CGVIEW_SERVER (default build/bin/cgview-server),
// CHROMIUM (default /usr/bin/chromium).
import { test } from 'node:test';
import assert from 'node:assert/strict';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { artifactsDir as artifacts, useViewer } from './harness.mjs';

const N = 16; // squares along a side: 2 N² triangles

/** A seeded permutation of 0..n-1 (a small LCG: the same file each run). */
function shuffled(n, seed) {
  const p = [...Array(n).keys()];
  let s = seed;
  for (let i = n - 1; i > 0; --i) {
    s = (s * 1103515245 + 12345) % 2147483648;
    const j = s % (i + 1);
    [p[i], p[j]] = [p[j], p[i]];
  }
  return p;
}

/** The grid: unit squares in z = 0 centred on the origin; vertices and faces shuffled. */
function makeGrid() {
  const grid = [];
  for (let j = 0; j <= N; ++j) for (let i = 0; i <= N; ++i) grid.push([i - N / 2, j - N / 2, 0]);
  const vperm = shuffled(grid.length, 7); // stored vertex k is grid vertex vperm[k]
  const where = new Array(grid.length);
  vperm.forEach((g, k) => (where[g] = k));
  const positions = vperm.map((g) => grid[g]);
  const tris = [];
  const v = (i, j) => where[j * (N + 1) + i];
  for (let j = 0; j < N; ++j) for (let i = 0; i < N; ++i) tris.push([v(i, j), v(i + 1, j), v(i + 1, j + 1)], [v(i, j), v(i + 1, j + 1), v(i, j + 1)]);
  const faces = shuffled(tris.length, 11).map((t) => tris[t]);
  return { positions, faces };
}

const mesh = makeGrid();
const file = path.join(fs.mkdtempSync(path.join(os.tmpdir(), 'cgview-selection-')), 'shuffled_grid.off');
fs.writeFileSync(
  file,
  `OFF\n${mesh.positions.length} ${mesh.faces.length} 0\n` + mesh.positions.map((p) => p.join(' ')).join('\n') + '\n' + mesh.faces.map((f) => `3 ${f.join(' ')}`).join('\n') + '\n',
);

const v = useViewer({ tmpPrefix: 'cgview-e2e-selection-', mesh: file });

const centroid = (f) => [0, 1, 2].map((a) => (mesh.positions[f[0]][a] + mesh.positions[f[1]][a] + mesh.positions[f[2]][a]) / 3);

/** x, y in CSS pixels of the canvas for a point, with the page's own matrices (column-major). */
function project(p, { width, height, viewProjection: m }) {
  const w = m[3] * p[0] + m[7] * p[1] + m[11] * p[2] + m[15];
  const x = (m[0] * p[0] + m[4] * p[1] + m[8] * p[2] + m[12]) / w;
  const y = (m[1] * p[0] + m[5] * p[1] + m[9] * p[2] + m[13]) / w;
  return [((x + 1) / 2) * width, ((1 - y) / 2) * height];
}

/** The rectangle rounded to whole pixels, each edge moved by a pixel or so until no point lies within half a pixel of it. */
function clearOf(points, rect) {
  const out = rect.map(Math.round);
  for (let e = 0; e < 4; ++e) {
    const a = e % 2; // 0: an x edge, 1: a y edge
    while (points.some((p) => Math.abs(p[a] - out[e]) <= 0.5)) out[e] += 1;
  }
  return out;
}

async function canvasBox() {
  return v.page.locator('#viewport canvas').boundingBox();
}

async function selection() {
  return v.page.evaluate(() => window.__cgview.selection);
}

/** Waits until the selection hook changes from `before` (a JSON string of it). */
async function waitSelectionChange(before) {
  await v.page.waitForFunction((b) => JSON.stringify(window.__cgview.selection) !== b, before, { timeout: 15000 });
  return selection();
}

async function drag(points) {
  const box = await canvasBox();
  const before = JSON.stringify(await selection());
  await v.page.mouse.move(box.x + points[0][0], box.y + points[0][1]);
  await v.page.mouse.down();
  for (const [x, y] of points.slice(1)) await v.page.mouse.move(box.x + x, box.y + y, { steps: 2 });
  await v.page.mouse.up();
  return waitSelectionChange(before);
}

/** Faces sharing a vertex with one of `sel` (grow), or those of `sel` sharing none with the others (shrink). */
function ring(sel, grow) {
  const inSel = new Set(sel);
  const touched = new Set();
  mesh.faces.forEach((f, i) => {
    if (inSel.has(i) === grow) f.forEach((x) => touched.add(x));
  });
  const out = [];
  mesh.faces.forEach((f, i) => {
    const touches = f.some((x) => touched.has(x));
    if (grow ? inSel.has(i) || touches : inSel.has(i) && !touches) out.push(i);
  });
  return out;
}

let boxIds = null;

test('the front view looks along -z', async () => {
  await v.page.locator('button[data-view="-z"]').click();
  const cam = await v.page.evaluate(() => window.__cgview.camera());
  assert.ok(Math.abs(cam.direction[2] + 1) < 1e-4, `looking along -z: ${JSON.stringify(cam)}`);
});

test('a box selection selects exactly the faces whose centroids project into it, by their stored ids', async () => {
  await v.page.locator('#select-tool').click();
  await v.page.waitForFunction(() => window.__cgview.selection?.ready === true, null, { timeout: 30000 });
  const view = await v.page.evaluate(() => window.__cgview.selectionView());
  const projected = mesh.faces.map((f) => project(centroid(f), view));
  // A box over the middle of the grid, its edges away from every centroid (no ties on the border).
  const [cx, cy] = project([0, 0, 0], view);
  const [ux] = project([1, 0, 0], view); // one grid unit in pixels
  const unit = ux - cx;
  assert.ok(unit > 10, `a square is ${unit} px`);
  const rect = clearOf(projected, [cx - 3.1 * unit, cy - 2.3 * unit, cx + 2.2 * unit, cy + 1.6 * unit]);
  const expected = projected.flatMap(([x, y], i) => (x >= rect[0] && x <= rect[2] && y >= rect[1] && y <= rect[3] ? [i] : []));
  assert.ok(expected.length > 20, `the box holds faces: ${expected.length}`);
  const camBefore = await v.page.evaluate(() => window.__cgview.camera());
  const s = await drag([
    [rect[0], rect[1]],
    [rect[2], rect[3]],
  ]);
  assert.deepEqual(await v.page.evaluate(() => window.__cgview.camera()), camBefore, 'the drag did not move the camera');
  assert.equal(s.kind, 'faces');
  assert.equal(s.count, expected.length, 'the count');
  assert.deepEqual(s.ids, expected, 'the stored ids');
  // Measured on the mesh streamed (Draco's 14-bit positions, one step of the
  // box's longest side): each corner within half a step of its stored place.
  const extent = Math.max(...[0, 1, 2].map((a) => Math.max(...mesh.positions.map((p) => p[a])) - Math.min(...mesh.positions.map((p) => p[a]))));
  const step = extent / ((1 << 14) - 1);
  assert.ok(Math.abs(s.area - 0.5 * expected.length) < expected.length * 2 * step, `the area: ${s.area}`);
  assert.equal(await v.page.locator('#selection-readout .selection-count').getAttribute('data-count'), String(expected.length));
  await v.page.locator('#viewport canvas').screenshot({ path: path.join(artifacts, 'e2e-selection-box.png') });
  await v.page.screenshot({ path: path.join(artifacts, 'e2e-selection-page.png') });
  // Shift adds: a second box to the right.
  const rect2 = clearOf(projected, [cx + 4.2 * unit, cy - 1.3 * unit, cx + 6.1 * unit, cy + 0.6 * unit]);
  const more = projected.flatMap(([x, y], i) => (x >= rect2[0] && x <= rect2[2] && y >= rect2[1] && y <= rect2[3] ? [i] : []));
  await v.page.keyboard.down('Shift');
  const s2 = await drag([
    [rect2[0], rect2[1]],
    [rect2[2], rect2[3]],
  ]);
  await v.page.keyboard.up('Shift');
  assert.deepEqual(
    s2.ids,
    [...expected, ...more].sort((a, b) => a - b),
  );
  boxIds = expected;
  assert.deepEqual(v.problems, [], v.describeProblems());
});

test('grow and shrink go by one ring of faces sharing a vertex', async () => {
  // Back to the first box alone.
  await v.page.locator('#selection-clear').click();
  await v.page.waitForFunction(() => window.__cgview.selection.count === 0);
  const view = await v.page.evaluate(() => window.__cgview.selectionView());
  const pts = boxIds.map((i) => project(centroid(mesh.faces[i]), view));
  const xs = pts.map((p) => p[0]),
    ys = pts.map((p) => p[1]);
  await drag([
    [Math.min(...xs) - 2, Math.min(...ys) - 2],
    [Math.max(...xs) + 2, Math.max(...ys) + 2],
  ]);
  let s = await selection();
  assert.deepEqual(s.ids, boxIds);
  const grown = ring(boxIds, true);
  let before = JSON.stringify(s);
  await v.page.locator('#selection-grow').click();
  s = await waitSelectionChange(before);
  assert.deepEqual(s.ids, grown);
  assert.ok(grown.length > boxIds.length);
  before = JSON.stringify(s);
  await v.page.locator('#selection-shrink').click();
  s = await waitSelectionChange(before);
  assert.deepEqual(s.ids, ring(grown, false));
  before = JSON.stringify(s);
  await v.page.locator('#selection-shrink').click();
  s = await waitSelectionChange(before);
  assert.deepEqual(s.ids, ring(ring(grown, false), false));
});

test('a lasso selects the faces whose centroids fall inside the polygon', async () => {
  const view = await v.page.evaluate(() => window.__cgview.selectionView());
  const [cx, cy] = project([0, 0, 0], view);
  const unit = project([1, 0, 0], view)[0] - cx;
  // A triangle, its corners off the centroids' lattice.
  const poly = [
    [cx - 5.3 * unit, cy + 4.1 * unit],
    [cx + 4.7 * unit, cy + 4.2 * unit],
    [cx - 0.2 * unit, cy - 5.1 * unit],
  ].map(([x, y]) => [Math.round(x), Math.round(y)]);
  const inside = (x, y) => {
    let c = false;
    for (let i = 0, j = 2; i < 3; j = i++) {
      const [xi, yi] = poly[i],
        [xj, yj] = poly[j];
      if (yi > y !== yj > y && x < ((xj - xi) * (y - yi)) / (yj - yi) + xi) c = !c;
    }
    return c;
  };
  const expected = mesh.faces.flatMap((f, i) => {
    const [x, y] = project(centroid(f), view);
    return inside(x, y) ? [i] : [];
  });
  await v.page.locator('#selection-shape-lasso').check();
  // The lasso's path: along the edges, many points each.
  const path = [];
  for (let k = 0; k < 3; ++k)
    for (let t = 0; t < 1; t += 0.1) path.push([poly[k][0] + t * (poly[(k + 1) % 3][0] - poly[k][0]), poly[k][1] + t * (poly[(k + 1) % 3][1] - poly[k][1])]);
  path.push(poly[0]);
  const s = await drag(path);
  // Points of the path are not exactly the triangle's edges (the mouse moves in steps): allow the
  // faces whose centroids lie within a pixel of an edge to differ.
  const near = new Set(
    mesh.faces.flatMap((f, i) => {
      const [x, y] = project(centroid(f), view);
      return [-1, 1].some((dx) => [-1, 1].some((dy) => inside(x + dx, y + dy) !== inside(x, y))) ? [i] : [];
    }),
  );
  const differ = [...new Set([...s.ids, ...expected])].filter((i) => s.ids.includes(i) !== expected.includes(i));
  assert.ok(
    differ.every((i) => near.has(i)),
    `only faces on the lasso's edge differ: ${differ}`,
  );
  assert.ok(expected.length > 30 && Math.abs(s.count - expected.length) <= near.size, `${s.count} vs ${expected.length}`);
  await v.page.locator('#selection-shape-box').check();
});

test('a click picks a face, and in vertex mode the nearest vertex of that face', async () => {
  const view = await v.page.evaluate(() => window.__cgview.selectionView());
  const f = 5;
  const [x, y] = project(centroid(mesh.faces[f]), view);
  const box = await canvasBox();
  let before = JSON.stringify(await selection());
  await v.page.mouse.click(box.x + x, box.y + y);
  let s = await waitSelectionChange(before);
  assert.deepEqual(s.ids, [f]);
  await v.page.locator('#selection-kind-vertices').check();
  await v.page.waitForFunction(() => window.__cgview.selection.kind === 'vertices');
  const corner = mesh.faces[f][1];
  const [px, py] = project(mesh.positions[corner], view);
  const [qx, qy] = [x + 0.8 * (px - x), y + 0.8 * (py - y)]; // inside the face, near that corner
  before = JSON.stringify(await selection());
  await v.page.mouse.click(box.x + qx, box.y + qy);
  s = await waitSelectionChange(before);
  assert.deepEqual(s.ids, [corner]);
  await v.page.locator('#selection-kind-faces').check();
  await v.page.waitForFunction(() => window.__cgview.selection.kind === 'faces');
});

test('extract_faces runs on the selection from the form: its output has exactly the selected faces', async () => {
  const view = await v.page.evaluate(() => window.__cgview.selectionView());
  const pts = boxIds.map((i) => project(centroid(mesh.faces[i]), view));
  const xs = pts.map((p) => p[0]),
    ys = pts.map((p) => p[1]);
  await drag([
    [Math.min(...xs) - 2, Math.min(...ys) - 2],
    [Math.max(...xs) + 2, Math.max(...ys) + 2],
  ]);
  assert.deepEqual((await selection()).ids, boxIds);
  await v.page.locator('#algorithm-menu').selectOption('extract_faces');
  const form = v.page.locator('form.algorithm-form[data-algorithm="extract_faces"]');
  await form.waitFor();
  await v.page.waitForFunction((n) => document.querySelector('[data-selection-kind="faces"]')?.textContent === `use current selection (${n} faces)`, boxIds.length);
  await form.locator('button.run').click();
  const li = v.page.locator('#jobs li.job[data-algorithm="extract_faces"][data-state="done"]').first();
  await li.waitFor({ timeout: 60000 });
  const jobId = await li.getAttribute('data-job-id');
  const job = await (await fetch(`${v.server.url}/api/v1/jobs/${jobId}`)).json();
  assert.deepEqual(job.params.faces, boxIds, 'the job got the stored ids');
  const off = await (await fetch(`${v.server.url}/api/v1/jobs/${jobId}/artifacts/mesh?format=off`)).text();
  const lines = off
    .trim()
    .split('\n')
    .filter((l) => l.trim() && !l.startsWith('#'));
  const [nv, nf] = lines[1].split(/\s+/).map(Number);
  assert.equal(nf, boxIds.length);
  const P = lines.slice(2, 2 + nv).map((l) => l.trim().split(/\s+/).map(Number));
  const got = lines.slice(2 + nv, 2 + nv + nf).map((l) => {
    const [, a, b, c] = l.trim().split(/\s+/).map(Number);
    return [0, 1, 2].map((k) => ((P[a][k] + P[b][k] + P[c][k]) / 3).toFixed(4)).join(' ');
  });
  const want = boxIds.map((i) =>
    centroid(mesh.faces[i])
      .map((x) => x.toFixed(4))
      .join(' '),
  );
  assert.deepEqual(got, want, 'the same faces, in the stored order');
});

test('an id out of range is a 400 naming it', async () => {
  const meshId = v.meshId;
  const r = await fetch(`${v.server.url}/api/v1/jobs`, {
    method: 'POST',
    headers: { 'Content-Type': 'application/json' },
    body: JSON.stringify({ algorithm: 'extract_faces', inputs: { mesh: meshId }, params: { faces: [3, mesh.faces.length] } }),
  });
  assert.equal(r.status, 400);
  const body = await r.json();
  assert.match(JSON.stringify(body), new RegExp(`face id ${mesh.faces.length} is out of range \\(the mesh has ${mesh.faces.length} faces\\)`));
  const schema = await (await fetch(`${v.server.url}/api/v1/algorithms`)).json();
  const faces = schema.algorithms.find((a) => a.name === 'extract_faces').params.properties.faces;
  assert.equal(faces['x-cgview-selection'], 'faces');
});

test('axis views (buttons and keys 1 / 3 / 7) look along the axes; reset frames again', async () => {
  await v.page.locator('#select-tool').click(); // the tool off
  const expect = { '+x': [1, 0, 0], '-x': [-1, 0, 0], '+y': [0, 1, 0], '-y': [0, -1, 0], '+z': [0, 0, 1], '-z': [0, 0, -1] };
  for (const [axis, d] of Object.entries(expect)) {
    await v.page.locator(`button[data-view="${axis}"]`).click();
    const cam = await v.page.evaluate(() => window.__cgview.camera());
    for (let a = 0; a < 3; ++a) assert.ok(Math.abs(cam.direction[a] - d[a]) < 1e-4, `${axis}: ${JSON.stringify(cam.direction)}`);
    const dist = Math.hypot(...cam.position.map((p, a) => p - cam.target[a]));
    for (let a = 0; a < 3; ++a) assert.ok(Math.abs(cam.target[a] - dist * d[a] - cam.position[a]) < 1e-4 * dist, 'the camera looks at the centre');
  }
  await v.page.locator('body').click({ position: { x: 5, y: 5 } });
  for (const [key, d] of [
    ['3', [-1, 0, 0]],
    ['7', [0, -1, 0]],
    ['Shift+1', [0, 0, 1]],
    ['1', [0, 0, -1]],
  ]) {
    await v.page.keyboard.press(key);
    const cam = await v.page.evaluate(() => window.__cgview.camera());
    for (let a = 0; a < 3; ++a) assert.ok(Math.abs(cam.direction[a] - d[a]) < 1e-4, `${key}: ${JSON.stringify(cam.direction)}`);
  }
  await v.page.locator('#view-reset').click();
  const cam = await v.page.evaluate(() => window.__cgview.camera());
  const want = [0.55, 0.35, 1].map((x) => -x / Math.hypot(0.55, 0.35, 1));
  for (let a = 0; a < 3; ++a) assert.ok(Math.abs(cam.direction[a] - want[a]) < 1e-3, `reset: ${JSON.stringify(cam.direction)}`);
});

test('fly mode: W moves the camera forward, A to the left; trackball mode rotates about the centre', async () => {
  await v.page.locator('#navigation-mode').selectOption('fly');
  await v.page.locator('body').click({ position: { x: 5, y: 5 } });
  const c0 = await v.page.evaluate(() => window.__cgview.camera());
  assert.equal(c0.mode, 'fly');
  await v.page.keyboard.down('w');
  await v.page.waitForTimeout(400);
  await v.page.keyboard.up('w');
  const c1 = await v.page.evaluate(() => window.__cgview.camera());
  const moved = c1.position.map((p, a) => p - c0.position[a]);
  const len = Math.hypot(...moved);
  assert.ok(len > 0.1, `the camera moved: ${len}`);
  for (let a = 0; a < 3; ++a) assert.ok(Math.abs(moved[a] / len - c0.direction[a]) < 1e-3, `forward: ${moved} vs ${c0.direction}`);
  await v.page.keyboard.down('a');
  await v.page.waitForTimeout(300);
  await v.page.keyboard.up('a');
  const c2 = await v.page.evaluate(() => window.__cgview.camera());
  const side = c2.position.map((p, a) => p - c1.position[a]);
  const right = [
    c1.direction[1] * c1.up[2] - c1.direction[2] * c1.up[1],
    c1.direction[2] * c1.up[0] - c1.direction[0] * c1.up[2],
    c1.direction[0] * c1.up[1] - c1.direction[1] * c1.up[0],
  ];
  assert.ok(side.reduce((s, x, a) => s + x * right[a], 0) < -0.05, `moved left: ${side}`);
  // Mouse-look turns the view.
  const box = await canvasBox();
  await v.page.mouse.move(box.x + box.width / 2, box.y + box.height / 2);
  await v.page.mouse.down();
  await v.page.mouse.move(box.x + box.width / 2 + 100, box.y + box.height / 2, { steps: 5 });
  await v.page.mouse.up();
  const c3 = await v.page.evaluate(() => window.__cgview.camera());
  assert.ok(Math.hypot(...c3.direction.map((d, a) => d - c2.direction[a])) > 0.1, 'mouse-look turned the camera');

  await v.page.locator('#navigation-mode').selectOption('trackball');
  await v.page.locator('#view-reset').click();
  const t0 = await v.page.evaluate(() => window.__cgview.camera());
  assert.equal(t0.mode, 'trackball');
  await v.page.mouse.move(box.x + box.width / 2, box.y + box.height / 2);
  await v.page.mouse.down();
  await v.page.mouse.move(box.x + box.width / 2 + 80, box.y + box.height / 2 + 60, { steps: 8 });
  await v.page.mouse.up();
  await v.page.waitForTimeout(300);
  const t1 = await v.page.evaluate(() => window.__cgview.camera());
  const r0 = Math.hypot(...t0.position.map((p, a) => p - t0.target[a]));
  const r1 = Math.hypot(...t1.position.map((p, a) => p - t1.target[a]));
  assert.ok(Math.hypot(...t1.direction.map((d, a) => d - t0.direction[a])) > 0.05, 'the trackball turned the camera');
  assert.ok(Math.abs(r1 - r0) < 1e-3 * r0, 'about the centre, at the same distance');
  await v.page.locator('#navigation-mode').selectOption('orbit');
  assert.deepEqual(v.problems, [], v.describeProblems());
});

test('visible only: a box over a cube seen from the front selects its front face; through selects all 12', async () => {
  const cube =
    'OFF\n8 12 0\n' +
    [
      [-1, -1, -1],
      [1, -1, -1],
      [1, 1, -1],
      [-1, 1, -1],
      [-1, -1, 1],
      [1, -1, 1],
      [1, 1, 1],
      [-1, 1, 1],
    ]
      .map((p) => p.join(' '))
      .join('\n') +
    '\n' +
    [
      [0, 2, 1],
      [0, 3, 2],
      [4, 5, 6],
      [4, 6, 7],
      [0, 1, 5],
      [0, 5, 4],
      [2, 3, 7],
      [2, 7, 6],
      [1, 2, 6],
      [1, 6, 5],
      [0, 4, 7],
      [0, 7, 3],
    ]
      .map((f) => `3 ${f.join(' ')}`)
      .join('\n') +
    '\n';
  const r = await fetch(`${v.server.url}/api/v1/meshes?name=cube.off`, { method: 'POST', body: cube });
  assert.equal(r.status, 201);
  const id = (await r.json()).id;
  await v.page.locator(`#mesh-list li.mesh[data-mesh-id="${id}"]`).click();
  await v.page.waitForFunction((i) => window.__cgview.lastLoaded?.id === i, id, { timeout: 30000 });
  await v.page.locator('button[data-view="-z"]').click();
  await v.page.locator('#select-tool').click();
  await v.page.waitForFunction((i) => window.__cgview.selection?.ready === true && window.__cgview.selection.meshId === i, id, { timeout: 30000 });
  const box = await canvasBox();
  const all = [
    [5, 5],
    [box.width - 5, box.height - 5],
  ];
  let s = await drag(all);
  assert.deepEqual(s.ids, [2, 3], 'the front face (z = +1) alone');
  await v.page.locator('#selection-through').check();
  await v.page.locator('#selection-clear').click();
  await v.page.waitForFunction(() => window.__cgview.selection.count === 0);
  s = await drag(all);
  assert.equal(s.count, 12, 'through: every face');
  await v.page.locator('#selection-through').uncheck();
  await v.page.locator('#select-tool').click();
  assert.deepEqual(v.problems, [], v.describeProblems());
});
