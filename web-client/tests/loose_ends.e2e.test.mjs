// End-to-end test of the viewer's loose ends, against the real server and
// Debian's chromium:
//   CGVIEW_SERVER=build/bin/cgview-server CGVIEW_SAMPLES=build/samples node --test tests/loose_ends.e2e.test.mjs
//
// On the elephant: a job's result added to the view comes back, listed in
// the Scene panel, when the page is reloaded, and no error is shown. The
// numbers read alike everywhere (four significant digits at most): the
// selection's area with its unit, the box readout, the field range's inputs
// (which keep the exact value when left as written). Panes compared side by
// side name their values' unit. The Display panel's sliders show their value
// beside them, following them. The account line's title holds all of its
// text. An upload's warnings and an import's are warnings: they stay longer
// than a notice, then go by themselves. With Z up, a box dragged over the top
// half of a box tall in its z selects the faces of high stored z, the
// highlight is drawn over them, and the axis drawn pointing up is labelled Z.
// The canvas is kept in build/test-artifacts/e2e-loose-ends-*.png.
//
// First impressions: a notice goes by itself while an error stays until
// dismissed (its button says so); a failed run's error goes when a rerun of
// the algorithm on the mesh succeeds; a few messages at most show, the
// newest first. Underscores show in the plugin name. Two uploads of one name
// are told apart in the mesh list.
//
// Environment: CGVIEW_SERVER, CGVIEW_SAMPLES (default build/samples), CHROMIUM.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { artifactsDir, boxCorners, doneRow, pngPixels, repo, settle, shortNumber, sleep, submitJob, useViewer } from './harness.mjs';

const samples = process.env.CGVIEW_SAMPLES ?? path.join(repo, 'build', 'samples');
const v = useViewer({ tmpPrefix: 'cgview-loose-ends-', mesh: path.join(samples, 'elephant.off') });

/** How long a notice and a warning stay (panels/messages.ts), and a margin. */
const NOTICE_MS = 5000;
const WARNING_MS = 10_000;
const MARGIN_MS = 2500;

async function show(id) {
  await v.page.locator(`#mesh-list li.mesh[data-mesh-id="${id}"]`).click();
  await v.page.waitForFunction((m) => window.__cgview.lastLoaded?.id === m, id, { timeout: 60000 });
  await settle(v.page);
}

async function upload(name, body) {
  const r = await fetch(`${v.server.url}/api/v1/meshes?name=${encodeURIComponent(name)}`, { method: 'POST', body });
  assert.equal(r.status, 201, await r.clone().text());
  return (await r.json()).id;
}

const sceneRow = (name) => v.page.locator('#scene .scene-object', { has: v.page.getByRole('button', { name, exact: true }) });
const alerts = () => v.page.getByRole('alert');

test('a result added to the view is listed in the Scene panel again after a reload, with no error', async () => {
  const { page } = v;
  const jobId = await submitJob(v, 'simplify', { mesh: v.meshId }, { target_faces: 1000 });
  const li = await doneRow(v, jobId);
  const name = 'elephant · simplify 1000';
  await li.locator('.artifact-mesh[data-artifact="mesh"]').getByRole('button', { name: 'Add to view' }).click();
  await sceneRow(name).waitFor({ timeout: 30000 });
  await page.waitForFunction(() => window.__cgview.scene.objects.length === 2 && window.__cgview.scene.objects.every((o) => o.loaded));
  // The address holds the result, by its job.
  await page.waitForFunction(
    (id) => atob((new URLSearchParams(location.hash.slice(1)).get('view') ?? '').replace(/-/g, '+').replace(/_/g, '/')).includes(`job:${id}/mesh`),
    jobId,
    { timeout: 10000 },
  );

  await page.reload();
  await page.waitForFunction(() => window.__cgview?.viewRestored != null, null, { timeout: 60000 });
  assert.deepEqual(await page.evaluate(() => window.__cgview.viewRestored.error ?? null), null, 'the link opened');
  await sceneRow(name).waitFor({ timeout: 30000 });
  assert.ok(
    await sceneRow(name)
      .getByRole('checkbox', { name: `Show ${name}` })
      .isChecked(),
    'the result is shown',
  );
  await page.waitForFunction(() => window.__cgview.scene.objects[1]?.loaded, null, { timeout: 30000 });
  assert.equal(await alerts().count(), 0, `no error: ${await alerts().allInnerTexts()}`);
  assert.equal(await page.evaluate(() => window.__cgview.lastError ?? null), null);
  // Back to the elephant alone for what follows.
  await sceneRow(name)
    .getByRole('button', { name: `Remove ${name} from the scene` })
    .click();
  await page.waitForFunction(() => window.__cgview.scene.objects.length === 1);
  assert.deepEqual(v.problems, [], v.describeProblems());
});

test('numbers read alike: the box readout, the field range (exact when left as written), compared panes with their unit', async () => {
  const { page } = v;
  await page.getByLabel('Bounding box').check();
  const readout = page.locator('#overlay-readout');
  await page.waitForFunction(() => /^Box /.test(document.querySelector('#overlay-readout')?.textContent ?? ''));
  const sides = /^Box (\S+) × (\S+) × (\S+)/.exec(await readout.innerText());
  assert.ok(sides, await readout.innerText());
  // The elephant's box is 0.7204 × 1 × 0.6030.
  assert.deepEqual(
    sides.slice(1).map((s, i) => Math.abs(shortNumber(s, `side ${i}`) - [0.7204, 1, 0.603][i]) < 2e-3),
    [true, true, true],
    sides[0],
  );
  await page.getByLabel('Bounding box').uncheck();

  const jobId = await submitJob(v, 'curvature', { mesh: v.meshId });
  const li = await doneRow(v, jobId);
  await li.locator('.artifact[data-artifact="mean_curvature"]').getByRole('button', { name: 'Show' }).click();
  await page.waitForFunction((id) => window.__cgview.lastField?.jobId === id && window.__cgview.lastField.artifact === 'mean_curvature', jobId, { timeout: 30000 });
  const exact = await page.evaluate(() => window.__cgview.lastField.range);
  const min = page.getByLabel('Field minimum');
  const max = page.getByLabel('Field maximum');
  const shownMin = shortNumber(await min.inputValue(), 'the field minimum');
  const shownMax = shortNumber(await max.inputValue(), 'the field maximum');
  assert.ok(Math.abs(shownMin - exact[0]) <= 5e-4 * Math.abs(exact[0]) && Math.abs(shownMax - exact[1]) <= 5e-4 * Math.abs(exact[1]), `${shownMin} … ${shownMax} for ${exact}`);
  // The maximum typed in, the minimum left as written: the minimum stays exact.
  const typed = exact[0] + 0.5 * (exact[1] - exact[0]);
  await max.fill(String(typed));
  await max.dispatchEvent('change');
  await page.waitForFunction((hi) => Math.abs(window.__cgview.lastField.range[1] - hi) < 1e-9, typed);
  assert.equal(await page.evaluate(() => window.__cgview.lastField.range[0]), exact[0], 'the minimum left as written is the exact one');

  // Compared side by side: each pane's legend says what its values are and their unit.
  await li.getByRole('button', { name: 'Compare', exact: true }).click();
  await page.waitForFunction(() => window.__cgview.lastCompare?.panes.length === 2, null, { timeout: 60000 });
  const titles = (await page.locator('.compare-view .compare-pane .legend .legend-title').allInnerTexts()).map((t) => t.replace(/\s+/g, ' '));
  assert.ok(titles.includes('curvature · mean_curvature (mesh units⁻¹)'), `pane titles: ${titles}`);
  assert.ok(titles.includes('curvature · gaussian_curvature (mesh units⁻²)'), `pane titles: ${titles}`);
  await page.locator('#leave-compare').click();
  await page.locator('#leave-compare').waitFor({ state: 'hidden' });
  assert.deepEqual(v.problems, [], v.describeProblems());
});

test("the Display panel's sliders show their value beside them, following them", async () => {
  const { page } = v;
  const display = page.locator('#display');
  const valueOf = (name) => display.locator('label', { has: page.getByRole('slider', { name, exact: true }) }).locator('.slider-value');
  for (const [name, value, text] of [
    ['Roughness', '0.8', '0.8'],
    ['Metalness', '0.35', '0.35'],
    ['Normal length', '0.1', '10 % of diagonal'],
  ]) {
    const slider = display.getByRole('slider', { name, exact: true });
    const before = Number((await valueOf(name).innerText()).split(' ')[0]);
    const scale = name === 'Normal length' ? 100 : 1;
    assert.ok(Math.abs(before - scale * Number(await slider.inputValue())) < 1e-9, `${name}: the value shown, ${before}, is the slider's`);
    await slider.fill(value);
    assert.equal(await valueOf(name).innerText(), text, `${name} after moving it`);
  }
  assert.deepEqual(v.problems, [], v.describeProblems());
});

test('the account line has its full text as its title', async () => {
  const usage = v.page.locator('#account .account-usage');
  await usage.waitFor();
  const text = await usage.textContent();
  assert.ok(text.length > 0);
  assert.equal(await usage.getAttribute('title'), text);
});

test("an upload's warnings and an import's are warnings: they stay longer than a notice, then go", async () => {
  const { page } = v;
  const dir = fs.mkdtempSync(path.join(os.tmpdir(), 'cgview-loose-ends-files-'));
  try {
    // A box whose OBJ names a material library not uploaded with it.
    const box = boxCorners();
    const corners = box.corners.map((p) => `v ${p.join(' ')}`);
    const faces = box.triangles.map((t) => `f ${t.map((i) => i + 1).join(' ')}`);
    const obj = path.join(dir, 'boxed.obj');
    fs.writeFileSync(obj, `mtllib boxed.mtl\n${corners.join('\n')}\n${faces.join('\n')}\n`);
    await page.setInputFiles('#file-input', obj);
    const uploadWarning = page.getByRole('status').filter({ hasText: "boxed.obj: the OBJ names the material library 'boxed.mtl'" });
    await uploadWarning.waitFor({ timeout: 30000 }).catch(async (e) => {
      const shown = await page.locator('#messages .message').allInnerTexts();
      throw new Error(
        `no warning of the upload: ${e.message}\nmessages: ${JSON.stringify(shown)}, last error: ${await page.evaluate(() => window.__cgview.lastError)}${v.describeProblems()}`,
      );
    });
    // The box shown: the values below are for its 12 faces.
    assert.match(await uploadWarning.getAttribute('class'), /\bwarning\b/, "the upload's warning");
    await page.waitForFunction(() => window.__cgview.lastLoaded?.faces === 12, null, { timeout: 60000 });
    // A value per face of the box, one missing.
    const txt = path.join(dir, 'gappy.txt');
    fs.writeFileSync(txt, Array.from({ length: 12 }, (_, i) => (i === 3 ? 'nan' : String(i))).join('\n') + '\n');
    await page.setInputFiles('#file-input', txt);
    const importWarning = page.getByRole('status').filter({ hasText: /^gappy\.txt: 1 of the 12 values are missing/ });
    await importWarning.waitFor({ timeout: 30000 });
    const start = Date.now();
    assert.match(await importWarning.getAttribute('class'), /\bwarning\b/, "the import's warning");

    await sleep(NOTICE_MS + MARGIN_MS - (Date.now() - start));
    assert.ok(await importWarning.isVisible(), 'a warning outlasts a notice');
    await page.waitForFunction(() => document.querySelectorAll('#messages .message.warning').length === 0, null, { timeout: WARNING_MS + MARGIN_MS });
    assert.equal(await alerts().count(), 0, `no error: ${await alerts().allInnerTexts()}`);
  } finally {
    fs.rmSync(dir, { recursive: true, force: true });
  }
  assert.deepEqual(v.problems, [], v.describeProblems());
});

/** A box of sides sx × sy × sz about the origin, each side cut in n × n squares, as OFF text, its faces turned outwards. */
function cutBoxOff(sx, sy, sz, n) {
  const vertices = [];
  const faces = [];
  const side = (origin, u, w) => {
    const base = vertices.length;
    for (let j = 0; j <= n; ++j) for (let i = 0; i <= n; ++i) vertices.push(origin.map((o, k) => o + (i / n) * u[k] + (j / n) * w[k]));
    for (let j = 0; j < n; ++j) {
      for (let i = 0; i < n; ++i) {
        const a = base + j * (n + 1) + i;
        faces.push([a, a + 1, a + n + 2], [a, a + n + 2, a + n + 1]);
      }
    }
  };
  const [x, y, z] = [sx / 2, sy / 2, sz / 2];
  side([-x, -y, -z], [0, 2 * y, 0], [2 * x, 0, 0]); // z = -z
  side([-x, -y, z], [2 * x, 0, 0], [0, 2 * y, 0]); // z = +z
  side([-x, -y, -z], [2 * x, 0, 0], [0, 0, 2 * z]); // y = -y
  side([-x, y, -z], [0, 0, 2 * z], [2 * x, 0, 0]); // y = +y
  side([-x, -y, -z], [0, 0, 2 * z], [0, 2 * y, 0]); // x = -x
  side([x, -y, -z], [0, 2 * y, 0], [0, 0, 2 * z]); // x = +x
  return `OFF\n${vertices.length} ${faces.length} 0\n${vertices.map((p) => p.join(' ')).join('\n')}\n${faces.map((f) => `3 ${f.join(' ')}`).join('\n')}\n`;
}

/** The stored mesh as OFF: its vertices and faces, in the server's order. */
async function storedOff(id) {
  const r = await fetch(`${v.server.url}/api/v1/meshes/${id}/download?format=off`);
  assert.equal(r.status, 200);
  const words = (await r.text())
    .replace(/#.*$/gm, '')
    .split(/\s+/)
    .filter((w) => w.length);
  assert.equal(words[0], 'OFF');
  const [nv, nf] = [Number(words[1]), Number(words[2])];
  const vertices = [];
  let k = 4;
  for (let i = 0; i < nv; ++i, k += 3) vertices.push([Number(words[k]), Number(words[k + 1]), Number(words[k + 2])]);
  const faces = [];
  for (let i = 0; i < nf; ++i) {
    const m = Number(words[k]);
    faces.push(words.slice(k + 1, k + 1 + m).map(Number));
    k += m + 1;
  }
  return { vertices, faces };
}

/** The box [x0, y0, x1, y1] of the pixels `is` holds, their count, and the mean y. */
function pixelBox({ width, height, data }, is) {
  const box = [Infinity, Infinity, -Infinity, -Infinity];
  let n = 0;
  let sumY = 0;
  for (let y = 0; y < height; ++y) {
    for (let x = 0; x < width; ++x) {
      const i = 4 * (y * width + x);
      if (!is(data[i], data[i + 1], data[i + 2])) continue;
      ++n;
      sumY += y;
      box[0] = Math.min(box[0], x);
      box[1] = Math.min(box[1], y);
      box[2] = Math.max(box[2], x);
      box[3] = Math.max(box[3], y);
    }
  }
  return { box, n, meanY: n ? sumY / n : NaN };
}

/** Away from the background, #1b1d22. */
const isDrawn = (r, g, b) => Math.abs(r - 0x1b) + Math.abs(g - 0x1d) + Math.abs(b - 0x22) > 40;
/** The selection's highlight, #ff2d75 over the surface. */
const isHighlight = (r, g, b) => r > 150 && b > g + 15 && b > 0.25 * r;

function hue(r, g, b) {
  const max = Math.max(r, g, b);
  const min = Math.min(r, g, b);
  if (max < 60 || max - min < 0.4 * max) return null;
  let h;
  if (max === r) h = (60 * (g - b)) / (max - min);
  else if (max === g) h = 120 + (60 * (b - r)) / (max - min);
  else h = 240 + (60 * (r - g)) / (max - min);
  return (h + 360) % 360;
}
/** The Y axis's green (its line and label). */
const isAxisGreen = (r, g, b) => {
  const h = hue(r, g, b);
  return h !== null && h >= 95 && h <= 140;
};
/** The Z axis's blue (its line and label). */
const isAxisBlue = (r, g, b) => {
  const h = hue(r, g, b);
  return h !== null && h >= 200 && h <= 245;
};

async function canvasPixels(name) {
  await settle(v.page);
  const png = await v.page.locator('#viewport canvas').screenshot();
  fs.writeFileSync(path.join(artifactsDir, `e2e-loose-ends-${name}.png`), png);
  return pngPixels(v.page, png);
}

test('Z up: a box over the top half of the drawn mesh selects the faces of high stored z, highlighted there; the axis pointing up is Z', async () => {
  const { page } = v;
  const id = await upload('tall.off', cutBoxOff(1, 1, 2, 4));
  await show(id);
  await page.getByLabel('Up axis').selectOption('z');
  await page.waitForFunction(() => window.__cgview.display?.up === 'z');
  await page.locator('#fit').click();
  const drawn = pixelBox(await canvasPixels('z-up'), isDrawn);
  const [x0, y0, x1, y1] = drawn.box;
  assert.ok(y1 - y0 > 1.5 * (x1 - x0), `the box stands: ${drawn.box}`);

  const selectTool = page.locator('#selection').getByRole('button', { name: 'Select', exact: true });
  await selectTool.click();
  await page.waitForFunction(() => window.__cgview.selection?.ready === true, null, { timeout: 30000 });
  // Through: the faces behind count too, so every face of the top half is expected.
  await page.getByLabel('Through (hidden too)').check();
  const canvas = await page.locator('#viewport canvas').boundingBox();
  const midY = (y0 + y1) / 2;
  await page.mouse.move(canvas.x + x0 - 10, canvas.y + y0 - 10);
  await page.mouse.down();
  await page.mouse.move(canvas.x + x1 + 10, canvas.y + midY - 5, { steps: 4 });
  await page.mouse.up();
  await page.waitForFunction(() => window.__cgview.selection?.count > 0, null, { timeout: 10000 });
  const ids = await page.evaluate(() => window.__cgview.selection.ids);
  const { vertices, faces } = await storedOff(id);
  const z = (f) => faces[f].reduce((s, vi) => s + vertices[vi][2], 0) / faces[f].length;
  // The camera looks a little from the side: faces just below the middle may show above the middle of the picture, none of the lower half's lower part.
  const low = ids.filter((f) => z(f) <= 0);
  assert.ok(low.length <= 0.1 * ids.length, `the faces selected are in the upper half of z: ${ids.length} selected, ${low.length} low`);
  assert.deepEqual(
    low.filter((f) => z(f) < -0.5),
    [],
    'none of the lower quarter',
  );
  // The top (z = 1) is seen edge on from the front: its faces, and those of the sides' upper quarter, are all taken.
  const expected = faces.map((_, f) => f).filter((f) => z(f) > 0.55);
  assert.deepEqual(
    expected.filter((f) => !ids.includes(f)),
    [],
    `the faces high in z are selected`,
  );

  // The highlight is drawn where they are: over the top half of the drawn box.
  const highlight = pixelBox(await canvasPixels('z-up-selection'), isHighlight);
  assert.ok(highlight.n > 200, `the highlight is drawn: ${highlight.n} pixels`);
  assert.ok(
    highlight.box[3] <= midY + 0.1 * (y1 - y0) && highlight.box[1] >= y0 - 8 && highlight.meanY < midY,
    `the highlight ${highlight.box} over the top half ${[x0, y0, x1, midY]}`,
  );
  await selectTool.click();

  // The axes of the mesh, from its lowest corner: Z (blue) points up, its label half way up
  // the box; Y (green) goes away from the camera, all of it low (world axes have Y up).
  await page.getByLabel('Axes').check();
  const pixels = await canvasPixels('z-up-axes');
  const blue = pixelBox(pixels, isAxisBlue);
  const green = pixelBox(pixels, isAxisGreen);
  assert.ok(blue.n > 50 && green.n > 20, `both axes drawn: ${blue.n} blue, ${green.n} green pixels`);
  assert.ok(blue.box[1] < midY, `the Z axis reaches above the middle: ${blue.box}, the box ${drawn.box}`);
  assert.ok(green.box[1] > midY, `the Y axis stays below the middle: ${green.box}, the box ${drawn.box}`);
  await page.getByLabel('Axes').uncheck();
  assert.deepEqual(v.problems, [], v.describeProblems());
});

const messages = () => v.page.locator('#messages');

test("a notice goes by itself, an error stays until dismissed; a rerun that succeeds takes the failed run's error away", async () => {
  const { page } = v;
  await show(v.meshId);
  await page.getByRole('combobox', { name: 'Algorithm', exact: true }).selectOption('geodesic_distance');
  const form = page.locator('form.algorithm-form[data-algorithm="geodesic_distance"]');
  await form.waitFor();
  const sources = form.getByLabel('Source vertices', { exact: true });
  await sources.fill('99999999');
  await form.getByRole('button', { name: 'Run', exact: true }).click();
  const failure = messages()
    .getByRole('alert')
    .filter({ hasText: /^geodesic_distance failed: .*out of range/ });
  await failure.waitFor({ timeout: 60000 });

  // A notice, after the error: it goes by itself, the error stays.
  await page.getByRole('button', { name: 'Copy link', exact: true }).click();
  const notice = messages()
    .getByRole('status')
    .filter({ hasText: /^View link/ });
  await notice.waitFor({ timeout: 10000 });
  assert.equal(
    await messages()
      .locator('.message')
      .first()
      .innerText()
      .then((t) => t.startsWith('View link')),
    true,
    'the newest is on top',
  );
  await notice.waitFor({ state: 'detached', timeout: NOTICE_MS + MARGIN_MS });
  assert.ok(await failure.isVisible(), 'the error outlasts the notice');
  assert.ok(await failure.getByRole('button', { name: 'Dismiss' }).isVisible(), 'the error has a button to dismiss it');

  // The rerun that succeeds: the failure no longer holds, and goes.
  await sources.fill('0');
  await form.getByRole('button', { name: 'Run', exact: true }).click();
  await page.locator('#jobs li.job[data-algorithm="geodesic_distance"][data-state="done"]').first().waitFor({ timeout: 120000 });
  await failure.waitFor({ state: 'detached', timeout: 10000 });
  assert.deepEqual(v.problems, [], v.describeProblems());
});

test('a few messages at most show, the newest first, each dismissed by its button', async () => {
  const { page } = v;
  const dir = fs.mkdtempSync(path.join(os.tmpdir(), 'cgview-loose-ends-bad-'));
  try {
    for (let i = 1; i <= 5; ++i) {
      const bad = path.join(dir, `bad${i}.off`);
      fs.writeFileSync(bad, 'OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 9\n');
      await page.setInputFiles('#file-input', bad);
      await messages()
        .getByRole('alert')
        .filter({ hasText: `Upload of bad${i}.off failed` })
        .waitFor({ timeout: 30000 });
    }
    const shown = await messages().getByRole('alert').allInnerTexts();
    assert.equal(shown.length, 3, `three at most: ${JSON.stringify(shown)}`);
    assert.deepEqual(
      shown.map((t) => /bad(\d)\.off/.exec(t)?.[1]),
      ['5', '4', '3'],
      'the newest first',
    );
    // The stack never covers much of the sidebar: the mesh list's heading stays in reach below it.
    const stack = await messages().boundingBox();
    assert.ok(stack.height < 0.4 * page.viewportSize().height, `the messages take ${stack.height} px`);
    while ((await messages().getByRole('alert').count()) > 0) {
      await messages().getByRole('alert').first().getByRole('button', { name: 'Dismiss' }).click();
    }
  } finally {
    fs.rmSync(dir, { recursive: true, force: true });
  }
  assert.deepEqual(
    v.problems.filter((p) => !/(HTTP 400: POST|status of 400).*\/meshes\?name=bad\d\.off/.test(p)),
    [],
    v.describeProblems(),
  );
  v.problems.length = 0;
});

test('underscores show in the plugin name', async () => {
  const { page } = v;
  await page.getByRole('button', { name: 'Code', exact: true }).click();
  const name = page.getByRole('textbox', { name: 'Plugin name' });
  await name.waitFor();
  const before = await name.inputValue();
  // The same field with and without underscores, blurred (no caret): they must not look the same.
  const picture = async (text) => {
    await name.fill(text);
    await name.blur();
    return pngPixels(page, await name.screenshot());
  };
  const plain = await picture('');
  const underscored = await picture('____');
  let differ = 0;
  for (let i = 0; i < plain.data.length; i += 4) if (Math.abs(plain.data[i] - underscored.data[i]) > 40) ++differ;
  assert.ok(differ > 10, `the underscores are drawn: ${differ} pixels differ`);
  // Their whole height: a box of the line's height holds the font's descenders.
  const fits = await name.evaluate((e) => e.clientHeight >= parseFloat(getComputedStyle(e).fontSize) * 1.4);
  assert.ok(fits, 'the field is tall enough for its font');
  await name.fill(before);
  await page.getByRole('button', { name: 'Code', exact: true }).click();
  assert.deepEqual(v.problems, [], v.describeProblems());
});

test('two uploads of one name are told apart in the mesh list', async () => {
  const { page } = v;
  const first = await upload('twin.off', cutBoxOff(1, 1, 1, 1));
  const second = await upload('twin.off', cutBoxOff(1, 2, 1, 1));
  const row = (id) => page.locator(`#mesh-list li.mesh[data-mesh-id="${id}"]`);
  await row(first).waitFor({ timeout: 30000 });
  await row(second).waitFor({ timeout: 30000 });
  const twins = page.locator('#mesh-list').getByRole('button').filter({ hasText: 'twin.off' });
  assert.equal(await twins.count(), 2);
  const [a, b] = [await row(first).innerText(), await row(second).innerText()];
  assert.notEqual(a, b, 'the two rows read differently');
  for (const [id, text] of [
    [first, a],
    [second, b],
  ]) {
    assert.match(text, /twin\.off/, 'the name is shown as it is');
    assert.match(text, new RegExp(`\\d\\d:\\d\\d( · ${id.slice(0, 6)})?`), `its upload time (and id): ${text}`);
  }
  // Their buttons say which one they act on.
  const deletes = await twins.getByRole('button', { name: /^Delete twin\.off \(.+\)$/ }).evaluateAll((bs) => bs.map((b) => b.getAttribute('aria-label')));
  assert.equal(new Set(deletes).size, 2, `two different delete buttons: ${deletes}`);
  // A name of its own has no tag.
  const lonely = await upload('lonely.off', cutBoxOff(1, 1, 1, 1));
  await row(lonely).waitFor({ timeout: 30000 });
  assert.doesNotMatch(await row(lonely).innerText(), /\d\d:\d\d/);
  assert.deepEqual(v.problems, [], v.describeProblems());
});
