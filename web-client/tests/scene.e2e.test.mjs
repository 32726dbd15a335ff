// End-to-end test of the scene (several meshes at once)
// against the real server and Debian's chromium: `npm run test:e2e`, or
//   CGVIEW_SERVER=build/bin/cgview-server CGVIEW_SAMPLES=build/samples node --test tests/scene.e2e.test.mjs
//
// A cube (shown with a click: the default orange) and an icosahedron (added
// with "+": the scene's first colour, blue) are in the scene. The
// icosahedron moved right (its x in the Scene panel) shows blue right of
// the orange cube in the canvas; hidden, no blue is left; recoloured green,
// green shows; the bounding-box overlay measures the object picked in the
// Scene panel, scaled; in wireframe mode both are drawn as lines. "Fit all" frames both (their world boxes, projected by the
// page's camera and read from window.__cgview.scene, lie inside the
// canvas). Side by side: each pane (half of the canvas) shows one object's
// colour and not the other's, and a drag with the mouse changes both
// halves. A view link made then reopens both meshes with their transform,
// colour and the panes, and draws the same picture. A plain click shows one
// mesh alone again, a ctrl-click adds one; a link whose scene does not begin
// with its mesh is reported.
//
// Environment: CGVIEW_SERVER, CGVIEW_SAMPLES (default build/samples), CHROMIUM.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import fs from 'node:fs';
import path from 'node:path';
import { artifactsDir, isMeshOrange, pngPixels, repo, settle, useViewer } from './harness.mjs';

const samples = process.env.CGVIEW_SAMPLES ?? path.join(repo, 'build', 'samples');
const v = useViewer({ tmpPrefix: 'cgview-scene-', mesh: path.join(samples, 'cube.off') });

async function canvasPixels(page, name) {
  await settle(page);
  const png = await page.locator('#viewport canvas').screenshot();
  fs.writeFileSync(path.join(artifactsDir, `e2e-scene-${name}.png`), png);
  return pngPixels(page, png);
}

const isBlue = (r, g, b) => b > 60 && b > 1.3 * r && b > 1.05 * g && b - Math.min(r, g) > 0.3 * b; // #3f8fe0 lit
const isGreen = (r, g, b) => g > 60 && g > 1.4 * r && g > 1.4 * b; // #20c040 lit

/** Pixels of a colour: how many, and their mean x as a fraction of the width; within columns [x0, x1) of the width. */
function colourStats(img, is, x0 = 0, x1 = 1) {
  let n = 0;
  let sx = 0;
  for (let y = 0; y < img.height; ++y) {
    for (let x = Math.floor(x0 * img.width); x < Math.floor(x1 * img.width); ++x) {
      const i = (y * img.width + x) * 4;
      if (is(img.data[i], img.data[i + 1], img.data[i + 2])) {
        ++n;
        sx += x;
      }
    }
  }
  return { n, x: n ? sx / n / img.width : NaN };
}

/** Share of pixels in columns [x0, x1) that differ by more than 24 in a channel between two pictures. */
function changed(a, b, x0, x1) {
  let n = 0;
  let diff = 0;
  for (let y = 0; y < a.height; ++y) {
    for (let x = Math.floor(x0 * a.width); x < Math.floor(x1 * a.width); ++x) {
      const i = (y * a.width + x) * 4;
      ++n;
      if (Math.abs(a.data[i] - b.data[i]) > 24 || Math.abs(a.data[i + 1] - b.data[i + 1]) > 24 || Math.abs(a.data[i + 2] - b.data[i + 2]) > 24) ++diff;
    }
  }
  return diff / n;
}

const sceneObjects = (page) => page.evaluate(() => window.__cgview.scene.objects);

async function editRow(page, index, cls, value) {
  const input = page.locator(`#scene .scene-object[data-index="${index}"] .${cls}`);
  await input.fill(String(value));
  await input.dispatchEvent('change');
}

const inside = (box) => box && box[0] >= -1 && box[1] >= -1 && box[2] <= 1 && box[3] <= 1;

let ico = null;

test('a second mesh added with "+" shows beside the first, moves, hides and takes a colour', async () => {
  const { page, server, meshId } = v;
  const r = await fetch(`${server.url}/api/v1/meshes?name=icosahedron.off`, { method: 'POST', body: fs.readFileSync(path.join(samples, 'icosahedron.off')) });
  assert.equal(r.status, 201);
  ico = (await r.json()).id;
  await page.locator(`#mesh-list li.mesh[data-mesh-id="${ico}"] .add-to-scene`).click();
  await page.waitForFunction((id) => window.__cgview.scene.objects[1]?.mesh === id && window.__cgview.scene.objects[1].loaded, ico, { timeout: 30000 });
  // The first object is still the one the click showed.
  assert.equal(await page.evaluate(() => window.__cgview.lastLoaded.id), meshId);
  assert.equal(await page.locator('#scene .scene-object').count(), 2);

  // Move the icosahedron right by 4 (the cube spans [-1, 1], the icosahedron radius 1) and fit all.
  await editRow(page, 1, 'scene-t-x', 4);
  // Moved, it leaves the view framed on the cube.
  await page.waitForFunction(() => window.__cgview.scene.objects[1].box?.[2] > 1, null, { timeout: 15000 });
  let objects;
  await page.click('#scene-fit-all');
  // The hook is set at each frame: a loaded machine may take a while to draw the next one.
  await page
    .waitForFunction(() => window.__cgview.scene.objects.every((o) => o.box && o.box[0] >= -1 && o.box[1] >= -1 && o.box[2] <= 1 && o.box[3] <= 1), null, { timeout: 15000 })
    .catch(() => {});
  await settle(page);
  objects = await sceneObjects(page);
  assert.deepEqual(objects[1].position, [4, 0, 0]);
  for (const o of objects) assert.ok(inside(o.box), `fit all frames ${o.name}: ${JSON.stringify(o.box)}`);
  const centre = (o) => (o.box[0] + o.box[2]) / 2;
  assert.ok(centre(objects[1]) > centre(objects[0]) + 0.3, `the icosahedron is right of the cube: ${JSON.stringify(objects.map((o) => o.box))}`);

  const both = await canvasPixels(page, 'both');
  const orange = colourStats(both, isMeshOrange);
  const blue = colourStats(both, isBlue);
  assert.ok(orange.n > 500 && blue.n > 500, `both drawn: ${orange.n} orange, ${blue.n} blue pixels`);
  assert.ok(blue.x > 0.5 && blue.x > orange.x + 0.15, `blue (x ${blue.x.toFixed(2)}) is right of orange (x ${orange.x.toFixed(2)})`);

  // Hidden: the blue is gone, the orange stays.
  await page.locator('#scene .scene-object[data-index="1"] .scene-visible').uncheck();
  await page.waitForFunction(() => window.__cgview.scene.objects[1].visible === false);
  const hidden = await canvasPixels(page, 'hidden');
  assert.ok(colourStats(hidden, isBlue).n < 20, `no blue left: ${colourStats(hidden, isBlue).n}`);
  assert.ok(colourStats(hidden, isMeshOrange).n > 0.8 * orange.n, 'the cube stays');

  // Shown again, in green.
  await page.locator('#scene .scene-object[data-index="1"] .scene-visible').check();
  await page.locator('#scene .scene-object[data-index="1"] .scene-color').fill('#20c040');
  await page.waitForFunction(() => window.__cgview.scene.objects[1].color === '#20c040' && window.__cgview.scene.objects[1].visible);
  const green = await canvasPixels(page, 'green');
  const g = colourStats(green, isGreen);
  assert.ok(g.n > 0.5 * blue.n && g.x > 0.5, `green where the blue was: ${g.n} pixels at x ${g.x.toFixed(2)}`);
  assert.ok(colourStats(green, isBlue).n < 20, 'no blue left');
  objects = await sceneObjects(page);
  assert.deepEqual(
    objects.map((o) => o.mesh),
    [meshId, ico],
  );

  // The display mode is the scene's: in wireframe both objects are drawn as lines, each in its colour.
  await page.selectOption('#display-mode', 'wireframe');
  await page.waitForFunction(() => window.__cgview.display?.mode === 'wireframe');
  const wire = await canvasPixels(page, 'wireframe');
  const wg = colourStats(wire, isGreen).n;
  const wo = colourStats(wire, isMeshOrange).n;
  assert.ok(wg > 0 && wg < 0.5 * g.n, `the icosahedron in green lines: ${wg} pixels (${g.n} shaded)`);
  assert.ok(wo > 0 && wo < 0.5 * orange.n, `the cube in orange lines: ${wo} pixels (${orange.n} shaded)`);
  await page.selectOption('#display-mode', 'smooth');
  await page.waitForFunction(() => window.__cgview.display?.mode === 'smooth');

  // Overlays are those of the object picked in the Scene panel: the bounding box's size is the icosahedron's
  // (1.7013 across: vertices at ±0.5257 and ±0.8507), then twice that once scaled by 2, then the cube's again.
  const boxSize = (want) =>
    page.waitForFunction(
      (w) => {
        const size = window.__cgview.display?.size;
        return size && size.every((x) => Math.abs(x - w) < 1e-3);
      },
      want,
      { timeout: 10000 },
    );
  await page.locator('#overlay-bbox').check();
  await boxSize(2);
  await page.locator('#scene .scene-object[data-index="1"] .scene-name').click();
  await page.waitForFunction(() => window.__cgview.scene.picked === 1);
  await boxSize(1.7013);
  await editRow(page, 1, 'scene-scale', 2);
  await boxSize(3.4026);
  await editRow(page, 1, 'scene-scale', 1);
  await page.locator('#scene .scene-object[data-index="0"] .scene-name').click();
  await boxSize(2);
  await page.locator('#overlay-bbox').uncheck();
  await page.waitForFunction(() => window.__cgview.display?.overlays.bbox === false);
  assert.deepEqual(v.problems, [], v.describeProblems());
});

test('side by side: one object per pane, and a drag orbits both', async () => {
  const { page } = v;
  await page.click('#scene-side-by-side');
  await page.waitForFunction(() => window.__cgview.scene.panes === 2);
  await settle(page);
  const objects = await sceneObjects(page);
  assert.deepEqual(
    objects.map((o) => o.pane),
    [0, 1],
  );
  for (const o of objects) assert.ok(inside(o.box), `${o.name} inside its pane: ${JSON.stringify(o.box)}`);
  const before = await canvasPixels(page, 'panes');
  const left = { orange: colourStats(before, isMeshOrange, 0, 0.5).n, green: colourStats(before, isGreen, 0, 0.5).n };
  const right = { orange: colourStats(before, isMeshOrange, 0.5, 1).n, green: colourStats(before, isGreen, 0.5, 1).n };
  assert.ok(left.orange > 300 && left.green < 20, `the left pane shows the cube alone: ${JSON.stringify(left)}`);
  assert.ok(right.green > 300 && right.orange < 20, `the right pane shows the icosahedron alone: ${JSON.stringify(right)}`);

  // Drag in the left pane: the one camera turns, both panes change.
  const box = await page.locator('#viewport canvas').boundingBox();
  const cx = box.x + box.width * 0.25;
  const cy = box.y + box.height / 2;
  await page.mouse.move(cx, cy);
  await page.mouse.down();
  await page.mouse.move(cx + 80, cy + 30, { steps: 8 });
  await page.mouse.up();
  const after = await canvasPixels(page, 'panes-orbited');
  const dl = changed(before, after, 0, 0.5);
  const dr = changed(before, after, 0.5, 1);
  assert.ok(dl > 0.005 && dr > 0.005, `both panes changed: left ${dl.toFixed(4)}, right ${dr.toFixed(4)}`);
  const moved = await sceneObjects(page);
  for (const i of [0, 1]) assert.notDeepEqual(moved[i].box, objects[i].box, `${moved[i].name} moved on screen`);
  assert.deepEqual(v.problems, [], v.describeProblems());
});

test('a view link reopens both meshes with their transform, colour and panes, and the same picture', async () => {
  const { page, browser, meshId } = v;
  // Turn the cube too, so that the link holds the first object's transform.
  await editRow(page, 0, 'scene-r-z', 30);
  await editRow(page, 0, 'scene-scale', 0.75);
  await settle(page);
  await page.click('#copy-link');
  await page.waitForFunction(() => window.__cgview.lastLink !== null);
  const link = await page.evaluate(() => window.__cgview.lastLink);
  const original = await canvasPixels(page, 'link-original');
  const want = await sceneObjects(page);

  const other = await browser.newPage({ viewport: { width: 1280, height: 800 } });
  try {
    const errors = [];
    other.on('pageerror', (e) => errors.push(e.message));
    await other.goto(link);
    await other.waitForFunction(() => window.__cgview?.viewRestored !== null, null, { timeout: 60000 });
    assert.ok(!('error' in (await other.evaluate(() => window.__cgview.viewRestored))));
    await other.waitForFunction(() => window.__cgview.scene.panes === 2, null, { timeout: 30000 });
    const got = await sceneObjects(other);
    const strip = (os) => os.map(({ mesh, visible, color, position, rotation, scale, pane }) => ({ mesh, visible, color, position, rotation, scale, pane }));
    assert.deepEqual(strip(got), strip(want));
    assert.deepEqual(
      got.map((o) => o.mesh),
      [meshId, ico],
    );
    assert.deepEqual(got[0].rotation, [0, 0, 30]);
    assert.equal(got[0].scale, 0.75);
    for (let i = 0; i < 2; ++i) {
      for (let k = 0; k < 4; ++k) assert.ok(Math.abs(got[i].box[k] - want[i].box[k]) < 1e-3, `${got[i].name}'s place on screen: ${got[i].box} vs ${want[i].box}`);
    }
    const reopened = await canvasPixels(other, 'link-reopened');
    assert.ok(changed(original, reopened, 0, 1) < 0.01, 'the same picture');
    assert.deepEqual(errors, []);
  } finally {
    await other.close();
  }
  assert.deepEqual(v.problems, [], v.describeProblems());
});

test('a plain click shows one mesh alone again, a ctrl-click adds one; a link with a bad scene is reported', async () => {
  const { page, server, meshId } = v;
  await page.locator(`#mesh-list li.mesh[data-mesh-id="${ico}"]`).click();
  await page.waitForFunction((id) => window.__cgview.lastLoaded?.id === id, ico, { timeout: 30000 });
  await page.waitForFunction(() => window.__cgview.scene.objects.length === 1 && window.__cgview.scene.panes === 0);
  const alone = await canvasPixels(page, 'alone');
  assert.ok(colourStats(alone, isMeshOrange).n > 300, 'the icosahedron alone, in the material colour');
  assert.ok(colourStats(alone, isGreen).n < 20 && colourStats(alone, isBlue).n < 20);
  // A ctrl-click adds to the scene, as "+" does.
  await page.locator(`#mesh-list li.mesh[data-mesh-id="${meshId}"]`).click({ modifiers: ['Control'] });
  await page.waitForFunction(
    (id) => window.__cgview.scene.objects.length === 2 && window.__cgview.scene.objects[1].mesh === id && window.__cgview.scene.objects[1].loaded,
    meshId,
    { timeout: 30000 },
  );
  assert.equal(await page.evaluate(() => window.__cgview.lastLoaded.id), ico, 'the shown mesh stays');

  const bad = { v: 1, mesh: meshId, camera: { position: [0, 0, 5], target: [0, 0, 0], up: [0, 1, 0], fov: 40 }, scene: [{ mesh: ico }] };
  const hash = '#view=' + Buffer.from(JSON.stringify(bad)).toString('base64url');
  const other = await v.browser.newPage();
  try {
    await other.goto(`${server.url}/${hash}`);
    await other.waitForFunction(() => window.__cgview?.viewRestored !== null, null, { timeout: 30000 });
    const restored = await other.evaluate(() => window.__cgview.viewRestored);
    assert.match(restored.error, /scene must begin with its mesh/);
  } finally {
    await other.close();
  }
});
