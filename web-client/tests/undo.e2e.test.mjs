// End-to-end test of "Undo" for what destroys, against the real server and
// Debian's chromium:
//   CGVIEW_SERVER=build/bin/cgview-server CGVIEW_SAMPLES=build/samples node --test tests/undo.e2e.test.mjs
//
// A cube shown, an icosahedron beside it in the scene. Clearing a selection
// offers it back, and "Undo" gives back the same faces; the icosahedron
// taken out of the scene comes back where it was; leaving the side by side
// offers it back, and "Undo" shows the panes again. Deleting the mesh
// shown takes it out of the list and the view at once, but the server is
// asked only once "Undo" is no longer offered: undone in time, no DELETE is
// ever sent and the mesh comes back shown, with the scene around it; not
// undone, one DELETE is sent when the offer ends and the server forgets it.
//
// Environment: CGVIEW_SERVER, CGVIEW_SAMPLES (default build/samples), CHROMIUM.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import fs from 'node:fs';
import path from 'node:path';
import { repo, settle, sleep, useViewer } from './harness.mjs';

const samples = process.env.CGVIEW_SAMPLES ?? path.join(repo, 'build', 'samples');
const v = useViewer({ tmpPrefix: 'cgview-undo-', mesh: path.join(samples, 'cube.off') });
/** How long the page offers "Undo" (controllers/undo.ts), and a margin. */
const UNDO_MS = 6000;
const MARGIN_MS = 2000;

/** The "Undo" button of the notice that says `text`. */
const undoOf = (text) => v.page.locator('#messages .message', { hasText: text }).getByRole('button', { name: 'Undo', exact: true });

const deletes = [];
let ico = null;

test('a cleared selection is offered back, and "Undo" gives back the same faces', async () => {
  const { page } = v;
  page.on('request', (r) => {
    if (r.method() === 'DELETE') deletes.push(r.url());
  });
  await page.locator('#selection').getByRole('button', { name: 'Select', exact: true }).click();
  await page.waitForFunction(() => window.__cgview.selection?.ready === true, null, { timeout: 30000 });
  const canvas = await page.locator('#viewport canvas').boundingBox();
  await page.mouse.move(canvas.x + 20, canvas.y + canvas.height - 20);
  await page.mouse.down();
  await page.mouse.move(canvas.x + canvas.width - 20, canvas.y + 60, { steps: 4 });
  await page.mouse.up();
  await page.waitForFunction(() => window.__cgview.selection.count > 0);
  const selected = await page.evaluate(() => window.__cgview.selection.ids);

  await page.locator('#selection').getByRole('button', { name: 'Clear', exact: true }).click();
  await page.waitForFunction(() => window.__cgview.selection.count === 0);
  const undo = undoOf(`Selection of ${selected.length} faces cleared`);
  await undo.click();
  await page.waitForFunction((n) => window.__cgview.selection.count === n, selected.length);
  assert.deepEqual(await page.evaluate(() => window.__cgview.selection.ids), selected);
  assert.ok(await undo.isHidden(), 'the notice goes once undone');
  await page.locator('#selection').getByRole('button', { name: 'Clear', exact: true }).click();
  await page.locator('#selection').getByRole('button', { name: 'Select', exact: true }).click();
  assert.deepEqual(v.problems, [], v.describeProblems());
});

test('an object taken out of the scene, and leaving the side by side, are offered back', async () => {
  const { page, server } = v;
  const r = await fetch(`${server.url}/api/v1/meshes?name=icosahedron.off`, { method: 'POST', body: fs.readFileSync(path.join(samples, 'icosahedron.off')) });
  assert.equal(r.status, 201);
  ico = (await r.json()).id;
  await page.getByRole('button', { name: 'Add icosahedron.off to the scene', exact: true }).click();
  await page.waitForFunction((id) => window.__cgview.scene.objects[1]?.mesh === id && window.__cgview.scene.objects[1].loaded, ico, { timeout: 30000 });

  // Taken out of the scene (moved first), it comes back where it was.
  const moveX = page.locator('#scene .scene-object[data-index="1"] .scene-t-x');
  await moveX.fill('3');
  await moveX.dispatchEvent('change');
  await page.getByRole('button', { name: 'Remove icosahedron.off from the scene', exact: true }).click();
  await page.waitForFunction(() => window.__cgview.scene.objects.length === 1);
  await undoOf('icosahedron.off removed from the scene').click();
  await page.waitForFunction((id) => window.__cgview.scene.objects[1]?.mesh === id && window.__cgview.scene.objects[1].loaded, ico, { timeout: 30000 });
  assert.deepEqual((await page.evaluate(() => window.__cgview.scene.objects[1])).position, [3, 0, 0]);

  await page.locator('#scene').getByRole('button', { name: 'Side by side', exact: true }).click();
  await page.waitForFunction(() => window.__cgview.scene.panes === 2);

  await page.getByRole('button', { name: 'Leave comparison', exact: true }).click();
  await page.waitForFunction(() => window.__cgview.scene.panes === 0);
  await undoOf('Left the comparison').click();
  await page.waitForFunction(() => window.__cgview.scene.panes === 2, null, { timeout: 10000 });
  assert.ok(await page.getByRole('button', { name: 'Leave comparison', exact: true }).isVisible());
  await page.getByRole('button', { name: 'Leave comparison', exact: true }).click();
  await page.waitForFunction(() => window.__cgview.scene.panes === 0);
  assert.deepEqual(v.problems, [], v.describeProblems());
});

test('a mesh deleted and undone in time comes back shown, with its scene, and is never deleted on the server', async () => {
  const { page, server, meshId } = v;
  const item = page.locator(`#mesh-list li.mesh[data-mesh-id="${meshId}"]`);
  await page.getByRole('button', { name: 'Delete cube.off', exact: true }).click();
  await item.waitFor({ state: 'detached', timeout: 10000 });
  await page.waitForFunction(() => window.__cgview.lastLoaded === null && window.__cgview.scene.objects.length === 0);
  assert.equal((await fetch(`${server.url}/api/v1/meshes/${meshId}`)).status, 200, 'the server still has it while "Undo" is offered');
  await undoOf('Deleted cube.off').click();
  await item.waitFor({ timeout: 10000 });
  await page.waitForFunction((id) => window.__cgview.lastLoaded?.id === id, meshId, { timeout: 30000 });
  await page.waitForFunction(
    ([a, b]) => {
      const o = window.__cgview.scene.objects;
      return o.length === 2 && o[0].mesh === a && o[1].mesh === b && o[1].loaded;
    },
    [meshId, ico],
    { timeout: 30000 },
  );
  await sleep(UNDO_MS + MARGIN_MS);
  assert.deepEqual(deletes, [], 'no DELETE was sent');
  assert.equal((await fetch(`${server.url}/api/v1/meshes/${meshId}`)).status, 200, 'the server still has it');
  assert.deepEqual(v.problems, [], v.describeProblems());
});

test('a mesh deleted and not undone is deleted on the server once "Undo" is no longer offered', async () => {
  const { page, server } = v;
  const item = page.locator(`#mesh-list li.mesh[data-mesh-id="${ico}"]`);
  await page.getByRole('button', { name: 'Delete icosahedron.off', exact: true }).click();
  await item.waitFor({ state: 'detached', timeout: 10000 });
  await page.waitForFunction(() => window.__cgview.scene.objects.length === 1, null, { timeout: 10000 });
  assert.ok(await undoOf('Deleted icosahedron.off').isVisible());
  assert.deepEqual(deletes, [], 'nothing is deleted while "Undo" is offered');
  assert.equal((await fetch(`${server.url}/api/v1/meshes/${ico}`)).status, 200);
  await page.waitForFunction(() => window.__cgview.pendingUndo === 0, null, { timeout: UNDO_MS + 10000 });
  const gone = async () => (await fetch(`${server.url}/api/v1/meshes/${ico}`)).status === 404;
  for (let i = 0; i < 50 && !(await gone()); ++i) await sleep(200);
  assert.ok(await gone(), 'the server no longer has it');
  assert.equal(deletes.length, 1, `one DELETE: ${deletes.join(' ')}`);
  assert.match(deletes[0], new RegExp(`/api/v1/meshes/${ico}$`));
  await undoOf('Deleted icosahedron.off').waitFor({ state: 'detached', timeout: 5000 });
  await settle(page);
  assert.equal(await item.count(), 0, 'it stays out of the list');
  assert.deepEqual(v.problems, [], v.describeProblems());
});
