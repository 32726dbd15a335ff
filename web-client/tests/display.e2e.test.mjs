// End-to-end test of the Display panel (display modes, overlays, view links)
// against the real server and Debian's chromium: `npm run test:e2e`, or
//   CGVIEW_SERVER=build/bin/cgview-server CGVIEW_SAMPLES=build/samples node --test tests/display.e2e.test.mjs
//
// Display modes: a coarse sample (eight.off, 634 triangles, so that flat
// shading shows) is drawn in each mode in a canvas of a fixed size (the
// viewport pinned to VIEW_SIZE) from the fixed fit-to-view camera,
// downloaded with the Screenshot button, and compared with the committed
// reference picture tests/reference/<mode>.png within a tolerance
// (TOLERANCE, over the pixels that are not background in both: the mean
// absolute difference per channel, and the share of pixels where a channel
// differs by more than `far`). The references differ from each other by
// far more than that tolerance, which the test checks too, so that it can
// fail. After an intended change of the rendering, rewrite the references
// with
//   CGVIEW_UPDATE_REFERENCES=1 node --test tests/display.e2e.test.mjs
// and look at them before committing. The pictures drawn are kept in
// build/test-artifacts/display-<mode>.png.
//
// Overlays: the boundary and non-manifold edge counts the panel reads out on
// an open sample mesh equal the counts computed here from the OFF file, the
// box's size equals the OFF's extent, and the boundary edges and the normals
// are drawn. Vertex colours: a coloured sample shows its colours, and the
// material's with them off.
// Field range: a scalar field recoloured over a range typed in, over its
// 1-99% percentiles (computed here from the values the server serves) and
// back over its full range, without fetching it again; it keeps its colours
// in toon mode, and a view link reopens it with its map and range.
// View link: a camera moved with the mouse, a mode and overlays, "Copy
// link", the link opened in a new page: same camera, mode, overlays, and
// the same picture.
// Crease angle: a box drawn Smooth looks as it does Flat (its faces
// uniform), a coarse sphere Smooth does not (and looks as it does at 180°),
// and the box at 180° gets its averaged, melted look back.
// Up axis: a tall box along z written as a binary STL stands on screen (STL
// is Z up until chosen) and lies down with Y up.
//
// Environment: CGVIEW_SERVER, CGVIEW_SAMPLES (default build/samples),
// CHROMIUM, CGVIEW_UPDATE_REFERENCES.
import assert from 'node:assert/strict';
import fs from 'node:fs';
import path from 'node:path';
import {
  artifactsDir,
  boxCorners,
  boxOff,
  hueStats,
  orbitDrag,
  PICTURE_TOLERANCE,
  pictureDifference,
  pngPixels,
  repo,
  settle,
  test,
  useViewer,
  VIEW_BACKGROUND,
  webClient,
} from './harness.mjs';

const samples = process.env.CGVIEW_SAMPLES ?? path.join(repo, 'build', 'samples');
const referenceDir = path.join(webClient, 'tests', 'reference');
const update = process.env.CGVIEW_UPDATE_REFERENCES === '1';

const MODES = ['smooth', 'flat', 'wireframe', 'points', 'hidden-line', 'toon'];
const VIEW_SIZE = { width: 400, height: 300 };
/** A picture matches its reference when both hold (over the pixels that are not background in both). */
const TOLERANCE = PICTURE_TOLERANCE;

const v = useViewer({ tmpPrefix: 'cgview-display-', mesh: path.join(samples, 'eight.off') });

/** Pins the viewport (and so the canvas) to VIEW_SIZE, over the page, whatever the layout around it. */
async function pinViewport(page) {
  await page.addStyleTag({
    // The header over it, so that its buttons (Fit view, a wide navigation toolbar before them) stay clickable;
    // the pictures are the canvas's own pixels (the Screenshot button), which the header does not cover.
    content: `header.topbar { position: relative; z-index: 1001; }
      #viewport { position: fixed !important; left: 0; top: 0; z-index: 1000;
      width: ${VIEW_SIZE.width}px !important; height: ${VIEW_SIZE.height}px !important; }`,
  });
  await page.waitForFunction(({ width, height }) => {
    const c = document.querySelector('#viewport canvas');
    return c && c.width === width && c.height === height;
  }, VIEW_SIZE);
}

/** The canvas as a PNG, through the page's Screenshot button (a download). */
async function screenshot(page, name) {
  await settle(page);
  const [download] = await Promise.all([page.waitForEvent('download'), page.click('#screenshot')]);
  const file = path.join(artifactsDir, `display-${name}.png`);
  await download.saveAs(file);
  const png = fs.readFileSync(file);
  assert.deepEqual([...png.subarray(0, 8)], [0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a], 'a PNG');
  return png;
}

const difference = (page, a, b) => pictureDifference(page, a, b).then((d) => (assert.ok(!d.sizes, 'pictures of one size'), d));
const matches = (d) => d.same;

async function setMode(page, mode) {
  await page.selectOption('#display-mode', mode);
  await page.waitForFunction((m) => window.__cgview.display?.mode === m, mode);
}

test('each display mode draws like its reference picture', async () => {
  const { page } = v;
  await pinViewport(page);
  await page.click('#fit');
  fs.mkdirSync(referenceDir, { recursive: true });
  const drawn = {};
  for (const mode of MODES) {
    await setMode(page, mode);
    await page.click('#fit');
    const png = await screenshot(page, mode);
    assert.deepEqual(await pngPixels(page, png).then((p) => [p.width, p.height]), [VIEW_SIZE.width, VIEW_SIZE.height]);
    drawn[mode] = png;
    const reference = path.join(referenceDir, `${mode}.png`);
    if (update) fs.writeFileSync(reference, png);
    assert.ok(fs.existsSync(reference), `no reference picture ${reference}: make it with CGVIEW_UPDATE_REFERENCES=1`);
    const d = await difference(page, png, fs.readFileSync(reference));
    assert.ok(
      matches(d),
      `${mode} differs from its reference: ${JSON.stringify(d)} (tolerance ${JSON.stringify(TOLERANCE)}); see ${path.join(artifactsDir, `display-${mode}.png`)}`,
    );
  }
  // Each reference differs from every other one by far more than the tolerance: a mode drawn wrong cannot pass.
  for (let i = 0; i < MODES.length; ++i) {
    for (let j = i + 1; j < MODES.length; ++j) {
      const d = await difference(page, drawn[MODES[i]], drawn[MODES[j]]);
      assert.ok(d.meanAbs > 3 * TOLERANCE.meanAbs || d.farShare > 3 * TOLERANCE.farShare, `${MODES[i]} and ${MODES[j]} look alike: ${JSON.stringify(d)}`);
    }
  }
  await setMode(page, 'smooth');
  assert.deepEqual(v.problems, [], v.describeProblems());
});

/** Boundary (used by one face) and non-manifold (more than two) edges of an OFF file's polygons, and its extent. */
function offEdges(text) {
  const tokens = text
    .split('\n')
    .map((l) => l.replace(/#.*/, ''))
    .join(' ')
    .trim()
    .split(/\s+/);
  assert.equal(tokens[0], 'OFF');
  const [nv, nf] = [Number(tokens[1]), Number(tokens[2])];
  let k = 4;
  const lo = [Infinity, Infinity, Infinity];
  const hi = [-Infinity, -Infinity, -Infinity];
  for (let i = 0; i < nv; ++i) {
    for (let c = 0; c < 3; ++c) {
      const x = Number(tokens[k++]);
      lo[c] = Math.min(lo[c], x);
      hi[c] = Math.max(hi[c], x);
    }
  }
  const uses = new Map();
  for (let f = 0; f < nf; ++f) {
    const n = Number(tokens[k++]);
    const face = tokens.slice(k, k + n).map(Number);
    k += n;
    for (let i = 0; i < n; ++i) {
      const [a, b] = [face[i], face[(i + 1) % n]].sort((x, y) => x - y);
      uses.set(`${a}-${b}`, (uses.get(`${a}-${b}`) ?? 0) + 1);
    }
  }
  const counts = [...uses.values()];
  return { boundary: counts.filter((n) => n === 1).length, nonManifold: counts.filter((n) => n > 2).length, size: hi.map((h, c) => h - lo[c]) };
}

/** Pixels of a PNG where `is(r, g, b)`. */
async function countPixels(page, png, is) {
  const { data } = await pngPixels(page, png);
  let n = 0;
  for (let i = 0; i < data.length; i += 4) if (is(data[i], data[i + 1], data[i + 2])) ++n;
  return n;
}

/** Pixels of the boundary edges' colour (#ff3b3b, viewer/overlays.ts). */
const redPixels = (page, png) => countPixels(page, png, (r, g, b) => r > 200 && g < 110 && b < 110);

test('overlays: the edge counts on an open mesh equal those of its OFF file, the box its extent', async () => {
  const { page, server } = v;
  const file = path.join(samples, 'elephant-with-holes.off');
  const expected = offEdges(fs.readFileSync(file, 'utf8'));
  assert.ok(expected.boundary > 0, 'the sample is open');
  const r = await fetch(`${server.url}/api/v1/meshes?name=elephant-with-holes.off`, { method: 'POST', body: fs.readFileSync(file) });
  assert.equal(r.status, 201, await r.clone().text());
  const { id } = await r.json();
  await page.locator(`#mesh-list li.mesh[data-mesh-id="${id}"]`).click();
  await page.waitForFunction((id) => window.__cgview.lastLoaded?.id === id, id, { timeout: 60000 });
  await page.click('#fit');
  const plain = await screenshot(page, 'edges-off');

  await page.check('#overlay-edges');
  await page.check('#overlay-bbox');
  await page.waitForFunction(() => window.__cgview.display?.overlays.edges && window.__cgview.display.overlays.bbox && window.__cgview.display.boundaryEdges !== null);
  const shown = await page.evaluate(() => window.__cgview.display);
  assert.equal(shown.boundaryEdges, expected.boundary, 'boundary edges');
  assert.equal(shown.nonManifoldEdges, expected.nonManifold, 'non-manifold edges');
  const readout = await page.locator('#overlay-readout').innerText();
  assert.ok(readout.includes(`${expected.boundary} boundary edges, ${expected.nonManifold} non-manifold`), readout);
  for (let c = 0; c < 3; ++c) {
    assert.ok(Math.abs(shown.size[c] - expected.size[c]) <= 1e-3 * Math.max(...expected.size), `box size ${shown.size} vs the OFF's ${expected.size}`);
  }
  // Each side as the viewer writes numbers: an integer exact ("1"), any other to 4 significant digits.
  const sides = /Box (\S+) × (\S+) × (\S+)/.exec(readout);
  assert.ok(sides, readout);
  for (let c = 0; c < 3; ++c) {
    assert.match(sides[c + 1], /^\d+(\.\d+)?$/, readout);
    assert.ok(sides[c + 1].replace('.', '').replace(/^0+/, '').length <= 4, `4 significant digits at most: ${readout}`);
    assert.ok(Math.abs(Number(sides[c + 1]) - expected.size[c]) <= 5e-4 * Math.max(...expected.size), `the side ${c} as shown: ${readout} vs ${expected.size}`);
  }
  const withEdges = await screenshot(page, 'edges-on');
  const [before, after] = [await redPixels(page, plain), await redPixels(page, withEdges)];
  assert.ok(after > before + 50, `the boundary edges are drawn in red: ${before} red pixels before, ${after} after`);

  await page.uncheck('#overlay-edges');
  await page.uncheck('#overlay-bbox');
  await page.waitForFunction(() => window.__cgview.display?.overlays.edges === false && window.__cgview.display.overlays.bbox === false);

  // Vertex normals (cyan) and face normals (lime), longer with the slider.
  const cyan = (r, g, b) => r < 110 && g > 170 && b > 200;
  const lime = (r, g, b) => r > 140 && g > 220 && b < 130;
  const none = await screenshot(page, 'normals-off');
  await page.check('#overlay-vertex-normals');
  await page.check('#overlay-face-normals');
  await page.waitForFunction(() => window.__cgview.display?.overlays.vertexNormals && window.__cgview.display.overlays.faceNormals);
  const short = await screenshot(page, 'normals-on');
  await page.locator('#overlay-normal-length').fill('0.1');
  await page.waitForFunction(() => window.__cgview.display?.overlays.normalLength === 0.1);
  const long = await screenshot(page, 'normals-long');
  const counts = [];
  for (const png of [none, short, long]) counts.push([await countPixels(page, png, cyan), await countPixels(page, png, lime)]);
  assert.ok(counts[1][0] > counts[0][0] + 100 && counts[1][1] > counts[0][1] + 100, `vertex and face normals are drawn: ${JSON.stringify(counts)}`);
  assert.ok(counts[2][0] > counts[1][0] && counts[2][1] > counts[1][1], `longer normals cover more: ${JSON.stringify(counts)}`);
  await page.uncheck('#overlay-vertex-normals');
  await page.uncheck('#overlay-face-normals');
  await page.waitForFunction(() => window.__cgview.display?.overlays.vertexNormals === false && !window.__cgview.display.overlays.faceNormals);
  assert.deepEqual(v.problems, [], v.describeProblems());
});

test('a mesh with vertex colours shows them, or the material colour with them off', async () => {
  const { page, server } = v;
  const file = path.join(samples, 'colored_tetra.ply');
  const r = await fetch(`${server.url}/api/v1/meshes?name=colored_tetra.ply`, { method: 'POST', body: fs.readFileSync(file) });
  assert.equal(r.status, 201, await r.clone().text());
  const { id } = await r.json();
  await page.locator(`#mesh-list li.mesh[data-mesh-id="${id}"]`).click();
  await page.waitForFunction((id) => window.__cgview.lastLoaded?.id === id, id, { timeout: 60000 });
  await page.waitForFunction(() => window.__cgview.display?.object === 'surface');
  assert.ok(await page.locator('#display-vertex-colors').isVisible(), 'the switch shows for a mesh with colours');
  const coloured = hueStats(await pngPixels(page, await screenshot(page, 'colors-on')));
  await page.uncheck('#display-vertex-colors');
  await page.waitForFunction(() => window.__cgview.display?.vertexColors === false);
  const plain = hueStats(await pngPixels(page, await screenshot(page, 'colors-off')));
  assert.ok(coloured.distinct >= 3 && coloured.orange < 0.5, `the vertex colours: ${JSON.stringify(coloured)}`);
  assert.ok(plain.orange > 0.9, `the plain orange surface: ${JSON.stringify(plain)}`);
  await page.check('#display-vertex-colors');
  await page.waitForFunction(() => window.__cgview.display?.vertexColors === true);
  assert.deepEqual(v.problems, [], v.describeProblems());
});

test('the view link reopens the same view: camera, mode, overlays and picture', async () => {
  const { page, browser, meshId } = v;
  await pinViewport(page);
  await page.locator(`#mesh-list li.mesh[data-mesh-id="${meshId}"]`).click();
  await page.waitForFunction((id) => window.__cgview.lastLoaded?.id === id, meshId, { timeout: 60000 });
  await setMode(page, 'hidden-line');
  await page.selectOption('#display-preset', 'ceramic');
  await page.check('#overlay-axes');
  await page.waitForFunction(() => window.__cgview.display?.overlays.axes && window.__cgview.display.preset === 'ceramic');
  // Orbit and zoom with the mouse, then wait for the damping to stop.
  await orbitDrag(page, 60, 25);
  await page.mouse.wheel(0, -200);
  await settle(page);
  const first = await screenshot(page, 'link-first');

  await page.click('#copy-link');
  await page.waitForFunction(() => window.__cgview.lastLink !== null);
  const link = await page.evaluate(() => window.__cgview.lastLink);
  assert.match(link, /#view=[A-Za-z0-9_-]+$/);
  assert.equal(await page.inputValue('#view-link'), link, 'the panel shows the link');
  assert.ok(!/token|bearer/i.test(decodeURIComponent(link)), 'no token in the link');
  const state = JSON.parse(Buffer.from(link.split('#view=')[1], 'base64url').toString());
  assert.equal(state.mesh, meshId);
  assert.equal(state.display.mode, 'hidden-line');

  const other = await browser.newPage({ viewport: { width: 1280, height: 800 } });
  try {
    other.on('pageerror', (e) => v.problems.push(`pageerror (second page): ${e.message}`));
    await other.goto(link);
    await pinViewport(other);
    await other.waitForFunction(() => window.__cgview?.viewRestored !== null, null, { timeout: 60000 });
    const restored = await other.evaluate(() => window.__cgview.viewRestored);
    assert.ok(!restored.error, `restoring failed: ${restored.error}`);
    const close = (a, b) => a.every((x, i) => Math.abs(x - b[i]) < 1e-9);
    for (const k of ['position', 'target', 'up']) assert.ok(close(restored.camera[k], state.camera[k]), `camera ${k}: ${restored.camera[k]} vs ${state.camera[k]}`);
    assert.equal(restored.camera.fov, state.camera.fov);
    assert.equal(restored.mode, 'hidden-line');
    await other.waitForFunction(() => window.__cgview.display?.mode === 'hidden-line' && window.__cgview.display.overlays.axes);
    const shown = await other.evaluate(() => window.__cgview.display);
    assert.equal(shown.preset, 'ceramic');
    assert.equal(await other.inputValue('#display-mode'), 'hidden-line', 'the panel shows the mode');
    const second = await screenshot(other, 'link-second');
    const d = await difference(page, first, second);
    assert.ok(matches(d), `the reopened view differs: ${JSON.stringify(d)}`);
    // And it is not just any view: the fit-to-view picture differs.
    await other.click('#fit');
    const fitted = await screenshot(other, 'link-fitted');
    assert.ok(!matches(await difference(page, first, fitted)), 'the camera moved by the mouse is not the fitted one');
  } finally {
    await other.close();
  }
  assert.deepEqual(v.problems, [], v.describeProblems());
});

test('a field recolours over a range typed in, its 1-99% percentiles and its full range, and a view link keeps it', async () => {
  const { page, browser, server, meshId } = v;
  await pinViewport(page);
  await page.locator(`#mesh-list li.mesh[data-mesh-id="${meshId}"]`).click();
  await page.waitForFunction((id) => window.__cgview.lastLoaded?.id === id, meshId, { timeout: 60000 });
  await setMode(page, 'smooth');
  await page.locator('#algorithm-menu').selectOption('centroid_distance');
  await page.locator('form.algorithm-form[data-algorithm="centroid_distance"] button.run').click();
  const li = page.locator('#jobs li.job[data-algorithm="centroid_distance"][data-state="done"]').first();
  await li.waitFor({ timeout: 120000 });
  const jobId = await li.getAttribute('data-job-id');
  await page.waitForFunction((id) => window.__cgview.lastField?.jobId === id, jobId, { timeout: 60000 });
  const field = await page.evaluate(() => window.__cgview.lastField);
  const r = await fetch(`${server.url}/api/v1/jobs/${jobId}/artifacts/${encodeURIComponent(field.artifact)}?format=f32`);
  assert.equal(r.status, 200);
  const bytes = new Uint8Array(await r.arrayBuffer());
  const values = new Float32Array(bytes.buffer, bytes.byteOffset, bytes.byteLength / 4);
  const sorted = [...values].filter(Number.isFinite).sort((a, b) => a - b);
  const full = field.range;
  assert.ok(full[1] > full[0], `a field with a spread: ${full}`);
  assert.ok(await page.locator('#field-range').isVisible(), 'the range control shows with a field');
  await page.click('#fit');
  const fetches = [];
  page.on('request', (req) => {
    if (req.url().includes('/artifacts/')) fetches.push(req.url());
  });
  const before = await screenshot(page, 'field-full');

  // A range typed in: the middle half of the full range.
  const typed = [full[0] + 0.25 * (full[1] - full[0]), full[0] + 0.75 * (full[1] - full[0])];
  await page.fill('#field-min', String(typed[0]));
  await page.fill('#field-max', String(typed[1]));
  await page.locator('#field-max').dispatchEvent('change');
  await page.waitForFunction(([lo, hi]) => {
    const f = window.__cgview.lastField;
    return f && Math.abs(f.range[0] - lo) < 1e-9 && Math.abs(f.range[1] - hi) < 1e-9;
  }, typed);
  const legendMin = Number(await page.locator('#legend .legend-min').innerText());
  const legendMax = Number(await page.locator('#legend .legend-max').innerText());
  assert.ok(Math.abs(legendMin - typed[0]) <= 1e-3 * Math.abs(typed[0]) + 1e-9, `legend min ${legendMin} vs ${typed[0]}`);
  assert.ok(Math.abs(legendMax - typed[1]) <= 1e-3 * Math.abs(typed[1]) + 1e-9, `legend max ${legendMax} vs ${typed[1]}`);
  const narrowed = await screenshot(page, 'field-typed');
  assert.ok(!matches(await difference(page, before, narrowed)), 'a narrower range recolours the surface');

  // 1-99%: nearest-rank percentiles of the served values.
  const rank = (p) => sorted[Math.round((p / 100) * (sorted.length - 1))];
  await page.click('#field-clip');
  await page.waitForFunction(
    ([lo, hi]) => {
      const f = window.__cgview.lastField;
      return f && f.range[0] === lo && f.range[1] === hi;
    },
    [rank(1), rank(99)],
  );

  // Toon keeps the field's colours (turbo: several hues, no plain orange).
  await setMode(page, 'toon');
  const hues = hueStats(await pngPixels(page, await screenshot(page, 'field-toon')));
  assert.ok(hues.distinct >= 3, `the field's colours in toon mode: ${JSON.stringify(hues)}`);

  // The link keeps the field, its map and its range.
  await page.click('#copy-link');
  await page.waitForFunction(() => window.__cgview.lastLink?.includes('#view='));
  const link = await page.evaluate(() => window.__cgview.lastLink);
  const clippedPicture = await screenshot(page, 'field-link-first');
  const other = await browser.newPage({ viewport: { width: 1280, height: 800 } });
  try {
    await other.goto(link);
    await pinViewport(other);
    await other.waitForFunction(() => window.__cgview?.viewRestored !== null, null, { timeout: 60000 });
    const restored = await other.evaluate(() => window.__cgview.viewRestored);
    assert.ok(!restored.error, `restoring failed: ${restored.error}`);
    await other.waitForFunction(
      ([id, lo, hi]) => {
        const f = window.__cgview.lastField;
        return f && f.jobId === id && f.range[0] === lo && f.range[1] === hi;
      },
      [jobId, rank(1), rank(99)],
    );
    assert.equal((await other.evaluate(() => window.__cgview.lastField)).map, field.map);
    assert.equal(await other.evaluate(() => window.__cgview.display.mode), 'toon');
    const d = await difference(page, clippedPicture, await screenshot(other, 'field-link-second'));
    assert.ok(matches(d), `the reopened field differs: ${JSON.stringify(d)}`);
  } finally {
    await other.close();
  }

  // Full range again: the first picture's colours, in toon mode now, so compare the range only.
  await page.click('#field-full');
  await page.waitForFunction(([lo, hi]) => {
    const f = window.__cgview.lastField;
    return f && f.range[0] === lo && f.range[1] === hi;
  }, full);
  assert.deepEqual(fetches, [], 'a new range recolours without fetching the field again');
  await setMode(page, 'smooth');
  assert.deepEqual(v.problems, [], v.describeProblems());
});

/** Uploads `body` as `name` and shows it; resolves with its id. */
async function showUpload(name, body) {
  const { page, server } = v;
  const r = await fetch(`${server.url}/api/v1/meshes?name=${name}`, { method: 'POST', body });
  assert.equal(r.status, 201, await r.clone().text());
  const { id } = await r.json();
  await page.locator(`#mesh-list li.mesh[data-mesh-id="${id}"]`).click();
  await page.waitForFunction((id) => window.__cgview.lastLoaded?.id === id, id, { timeout: 60000 });
  await page.waitForFunction(() => window.__cgview.display?.object === 'surface');
  return id;
}

/** A UV sphere of `segments` around and `rings` from pole to pole, as OFF text (coarse: its facets show when flat-shaded). */
function sphereOff(segments, rings) {
  const points = [[0, 0, 1]];
  for (let i = 1; i < rings; ++i) {
    const t = (Math.PI * i) / rings;
    for (let j = 0; j < segments; ++j) {
      const p = (2 * Math.PI * j) / segments;
      points.push([Math.sin(t) * Math.cos(p), Math.sin(t) * Math.sin(p), Math.cos(t)]);
    }
  }
  points.push([0, 0, -1]);
  const ring = (i, j) => 1 + (i - 1) * segments + (j % segments);
  const faces = [];
  for (let j = 0; j < segments; ++j) faces.push([0, ring(1, j), ring(1, j + 1)]);
  for (let i = 1; i + 1 < rings; ++i) {
    for (let j = 0; j < segments; ++j) faces.push([ring(i, j), ring(i + 1, j), ring(i + 1, j + 1)], [ring(i, j), ring(i + 1, j + 1), ring(i, j + 1)]);
  }
  for (let j = 0; j < segments; ++j) faces.push([points.length - 1, ring(rings - 1, j + 1), ring(rings - 1, j)]);
  return `OFF\n${points.length} ${faces.length} 0\n${points.map((q) => q.map((x) => x.toFixed(6)).join(' ')).join('\n')}\n${faces.map((f) => `3 ${f.join(' ')}`).join('\n')}\n`;
}

/** The default material with no overlay, whatever the tests before left. */
async function plainDisplay(page) {
  await pinViewport(page);
  await setMode(page, 'smooth');
  await page.selectOption('#display-preset', 'default');
  for (const id of ['bbox', 'axes', 'vertex-normals', 'face-normals', 'edges']) await page.uncheck(`#overlay-${id}`);
  await page.waitForFunction(() => {
    const d = window.__cgview.display;
    return d?.preset === 'default' && Object.entries(d.overlays).every(([k, on]) => k === 'normalLength' || !on);
  });
}

async function setCrease(page, degrees) {
  await page.getByLabel('Crease angle').fill(String(degrees));
  await page.waitForFunction((d) => window.__cgview.display?.creaseAngle === d, degrees);
}

test("Smooth keeps a box's edges sharp (as Flat draws it), a coarse sphere smooth; 180° averages the normals across every edge", async () => {
  const { page } = v;
  await plainDisplay(page);
  assert.equal(await page.getByLabel('Crease angle').inputValue(), '60', 'the default crease angle');

  await showUpload('crease-box.off', boxOff(1, 0.6, 0.8));
  await page.click('#fit');
  assert.equal(await page.evaluate(() => window.__cgview.display.crease), 60, 'the box is drawn with split normals');
  const boxSmooth = await screenshot(page, 'crease-box-smooth');
  await setMode(page, 'flat');
  const boxFlat = await screenshot(page, 'crease-box-flat');
  const sharp = await difference(page, boxSmooth, boxFlat);
  assert.ok(sharp.same, `the box in Smooth looks as in Flat: ${JSON.stringify(sharp)}`);
  await setMode(page, 'smooth');
  await setCrease(page, 180);
  await page.waitForFunction(() => window.__cgview.display?.crease === null);
  const boxMelted = await screenshot(page, 'crease-box-180');
  const melted = await difference(page, boxMelted, boxFlat);
  assert.ok(!melted.same, `at 180° the box's normals are averaged across its edges: ${JSON.stringify(melted)}`);
  await setCrease(page, 60);

  await showUpload('crease-sphere.off', sphereOff(16, 10));
  await page.click('#fit');
  const sphereSmooth = await screenshot(page, 'crease-sphere-smooth');
  await setMode(page, 'flat');
  const sphereFlat = await screenshot(page, 'crease-sphere-flat');
  const facets = await difference(page, sphereSmooth, sphereFlat);
  assert.ok(!facets.same, `the sphere in Smooth shows no facets: ${JSON.stringify(facets)}`);
  await setMode(page, 'smooth');
  await setCrease(page, 180);
  const sphere180 = await screenshot(page, 'crease-sphere-180');
  const alike = await difference(page, sphereSmooth, sphere180);
  assert.ok(alike.same, `the sphere at 60° looks as at 180°: ${JSON.stringify(alike)}`);
  await setCrease(page, 60);

  // A file's own normals are kept: the slider says it does not apply.
  const { corners, triangles } = boxCorners();
  const obj = [...corners.map((c) => `v ${c.join(' ')}`), 'vn 0 0 1', ...triangles.map((t) => `f ${t.map((i) => `${i + 1}//1`).join(' ')}`)].join('\n');
  await showUpload('file-normals.obj', obj + '\n');
  assert.equal(await page.evaluate(() => window.__cgview.display.crease), null, "the file's normals are drawn");
  const slider = page.getByLabel('Crease angle');
  assert.ok(await slider.isDisabled(), 'the slider is off for a mesh with its own normals');
  assert.match(await slider.getAttribute('title'), /own normals/);
  assert.deepEqual(v.problems, [], v.describeProblems());
});

/** A binary STL of the triangles (corner triples). */
function binaryStl(corners, triangles) {
  const buffer = Buffer.alloc(84 + 50 * triangles.length);
  buffer.writeUInt32LE(triangles.length, 80);
  triangles.forEach((t, k) => {
    const at = 84 + 50 * k + 12; // the facet normal left zero: readers compute it
    t.forEach((c, i) => corners[c].forEach((x, j) => buffer.writeFloatLE(x, at + 12 * i + 4 * j)));
  });
  return buffer;
}

/** The box [x0, y0, x1, y1] of the pixels of a PNG that are not the background. */
async function drawnBox(page, png) {
  const { width, height, data } = await pngPixels(page, png);
  const box = [Infinity, Infinity, -Infinity, -Infinity];
  for (let y = 0; y < height; ++y) {
    for (let x = 0; x < width; ++x) {
      const i = 4 * (y * width + x);
      if (Math.abs(data[i] - VIEW_BACKGROUND[0]) + Math.abs(data[i + 1] - VIEW_BACKGROUND[1]) + Math.abs(data[i + 2] - VIEW_BACKGROUND[2]) <= 40) continue;
      box[0] = Math.min(box[0], x);
      box[1] = Math.min(box[1], y);
      box[2] = Math.max(box[2], x);
      box[3] = Math.max(box[3], y);
    }
  }
  return box;
}

test('an STL stands Z up until Y up is chosen, which lays it down', async () => {
  const { page } = v;
  await plainDisplay(page);
  const { corners, triangles } = boxCorners(0.2, 0.2, 2);
  await showUpload('tall.stl', binaryStl(corners, triangles));
  await page.waitForFunction(() => window.__cgview.display?.up === 'z');
  assert.equal(await page.getByLabel('Up axis').inputValue(), 'z');
  await page.click('#fit');
  const [x0, y0, x1, y1] = await drawnBox(page, await screenshot(page, 'stl-z-up'));
  assert.ok(y1 - y0 > 2 * (x1 - x0), `the box stands: ${[x0, y0, x1, y1]}`);

  await page.getByLabel('Up axis').selectOption('y');
  await page.waitForFunction(() => window.__cgview.display?.up === 'y');
  await page.click('#fit');
  const [a0, b0, a1, b1] = await drawnBox(page, await screenshot(page, 'stl-y-up'));
  assert.ok(a1 - a0 > b1 - b0, `the box lies: ${[a0, b0, a1, b1]}`);
  assert.deepEqual(v.problems, [], v.describeProblems());
});

test('a bad view link, or one whose mesh is gone, says so in the page', async () => {
  const { browser, server } = v;
  const other = await browser.newPage({ viewport: { width: 1280, height: 800 } });
  try {
    const errors = [];
    other.on('pageerror', (e) => errors.push(e.message));
    await other.goto(`${server.url}/#view=not-json`);
    await other.waitForFunction(() => window.__cgview?.viewRestored !== null, null, { timeout: 30000 });
    assert.match((await other.evaluate(() => window.__cgview.viewRestored)).error, /not base64url JSON/);
    await other.locator('#messages .message.error', { hasText: 'Cannot open the view link' }).waitFor();

    const gone = { v: 1, mesh: 'no-such-mesh', camera: { position: [0, 0, 3], target: [0, 0, 0], up: [0, 1, 0], fov: 40 } };
    await other.goto(`${server.url}/#view=${Buffer.from(JSON.stringify(gone)).toString('base64url')}`);
    await other.reload(); // a new hash alone does not reload the page
    await other.waitForFunction(() => window.__cgview?.viewRestored !== null, null, { timeout: 30000 });
    assert.match((await other.evaluate(() => window.__cgview.viewRestored)).error, /no-such-mesh .*does not exist or is not shared with you/);
    assert.deepEqual(errors, [], 'no uncaught errors');
  } finally {
    await other.close();
  }
});
