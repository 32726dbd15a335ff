// End-to-end test of the first screen and of uploads seen before, against the
// real server (with its sample meshes) and Debian's chromium: `npm run
// test:e2e`, or
//   CGVIEW_SERVER=build/bin/cgview-server CGVIEW_SAMPLES=build/samples node --test tests/first_screen.e2e.test.mjs
//
// The empty page shows a card over the view: "Drop a mesh here, or pick a
// sample", a button per sample and "Upload a mesh". The upload button opens
// the file picker; the mesh chosen is drawn and the card goes (the view
// under it takes the pointer again). The same file uploaded twice more
// leaves one entry in the mesh list, selected, and the page says it was
// already uploaded. Deleted, the view is empty and the card is back; a
// sample's button draws it. The canvas is kept in
// build/test-artifacts/e2e-first-screen-*.png.
//
// Environment: CGVIEW_SERVER, CHROMIUM.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { artifactsDir, isMeshOrange, pngPixels, settle, useViewer } from './harness.mjs';

const v = useViewer({ tmpPrefix: 'cgview-first-screen-' });

const card = () => v.page.getByRole('region', { name: 'Drop a mesh here, or pick a sample' });

async function orangePixels(name) {
  await settle(v.page);
  const png = await v.page.locator('#viewport canvas').screenshot();
  fs.writeFileSync(path.join(artifactsDir, `e2e-first-screen-${name}.png`), png);
  const img = await pngPixels(v.page, png);
  let n = 0;
  for (let i = 0; i < img.data.length; i += 4) if (isMeshOrange(img.data[i], img.data[i + 1], img.data[i + 2])) ++n;
  return n;
}

// A tetrahedron that no sample is.
const tetra = path.join(fs.mkdtempSync(path.join(os.tmpdir(), 'cgview-first-screen-files-')), 'tetra.off');
fs.writeFileSync(tetra, 'OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n');

test('the empty page shows the card; "Upload a mesh" draws a mesh and the card goes', async () => {
  const { page } = v;
  await card().waitFor();
  const samples = card().locator('button.first-screen-sample');
  const names = await samples.allInnerTexts();
  assert.ok(names.length >= 2 && names.length <= 3, `two or three samples: ${names}`);
  assert.equal(names[0], 'elephant', 'the elephant first');
  assert.ok(await card().getByRole('button', { name: 'Upload a mesh' }).isVisible());
  assert.ok((await orangePixels('empty')) < 20, 'nothing drawn yet');

  const [chooser] = await Promise.all([page.waitForEvent('filechooser'), card().getByRole('button', { name: 'Upload a mesh' }).click()]);
  await chooser.setFiles(tetra);
  await page.waitForFunction(() => window.__cgview.lastLoaded !== null, null, { timeout: 60000 });
  await card().waitFor({ state: 'hidden' });
  assert.ok((await orangePixels('uploaded')) > 200, 'the tetrahedron is drawn');
  // Nothing of the card is left over the view: its centre is the canvas's.
  const box = await page.locator('#viewport canvas').boundingBox();
  const hit = await page.evaluate(([x, y]) => document.elementFromPoint(x, y)?.tagName, [box.x + box.width / 2, box.y + box.height / 2]);
  assert.equal(hit, 'CANVAS');
  assert.deepEqual(v.problems, [], v.describeProblems());
});

test('the same file uploaded three times is one entry, selected, and the page says so', async () => {
  const { page, server } = v;
  const entries = page.locator('#mesh-list li.mesh', { has: page.locator('.mesh-name', { hasText: /^tetra\.off$/ }) });
  assert.equal(await entries.count(), 1);
  const id = await entries.getAttribute('data-mesh-id');
  // Another mesh shown, so that selecting the one uploaded shows.
  await page.locator('#mesh-list li.mesh', { has: page.locator('.mesh-name', { hasText: /^elephant\.off$/ }) }).click();
  await page.waitForFunction((old) => window.__cgview.lastLoaded?.id !== old, id, { timeout: 60000 });
  for (let i = 0; i < 2; ++i) {
    await page.setInputFiles('#file-input', tetra);
    await page.locator('#messages .message', { hasText: 'already uploaded as tetra.off' }).first().waitFor({ timeout: 30000 });
  }
  await page.waitForFunction((id) => window.__cgview.lastLoaded?.id === id, id, { timeout: 60000 });
  assert.equal(await entries.count(), 1, 'one entry in the mesh list');
  assert.match(await entries.getAttribute('class'), /selected/);
  const meshes = (await (await fetch(`${server.url}/api/v1/meshes`)).json()).meshes;
  assert.equal(meshes.filter((m) => m.name === 'tetra.off').length, 1, 'stored once');
  assert.deepEqual(v.problems, [], v.describeProblems());
});

test('with the scene empty again the card is back, and a sample button draws the sample', async () => {
  const { page } = v;
  const tetraRow = page.locator('#mesh-list li.mesh', { has: page.locator('.mesh-name', { hasText: /^tetra\.off$/ }) });
  await tetraRow.getByRole('button', { name: 'Delete tetra.off' }).click();
  await card().waitFor();
  assert.ok((await orangePixels('empty-again')) < 20, 'nothing drawn');
  await card().getByRole('button', { name: 'elephant', exact: true }).click();
  await page.waitForFunction(() => window.__cgview.lastLoaded?.faces === 5558, null, { timeout: 60000 });
  await card().waitFor({ state: 'hidden' });
  assert.ok((await orangePixels('sample')) > 1000, 'the elephant is drawn');
  assert.deepEqual(v.problems, [], v.describeProblems());
});
