// End-to-end test of big meshes (a preview first), against the real server
// (with its preview threshold lowered to 20k faces) and a real browser: a
// 320k-triangle torus first shows its decimated preview (at most 5k faces,
// with the "preview shown" badge), then the full mesh, and the camera does not
// move at the swap; a small mesh comes in one piece with no preview.  The
// triangle counts read from the page are checked against the mesh uploaded
// (an independent count) and the server's --preview-target.
//
// Environment: CGVIEW_SERVER (default build/bin/cgview-server),
// CHROMIUM (default /usr/bin/chromium), CGVIEW_SAMPLES (build/samples).
import { test } from 'node:test';
import assert from 'node:assert/strict';
import fs from 'node:fs';
import path from 'node:path';
import { artifactsDir, isMeshOrange, pngPixels, repo, useViewer } from './harness.mjs';

const PREVIEW_TARGET = 5000;
const v = useViewer({
  tmpPrefix: 'cgview-e2e-bigmesh-',
  serverArgs: ['--preview-faces', '20000', '--preview-target', String(PREVIEW_TARGET)],
});
const samples = process.env.CGVIEW_SAMPLES ?? path.join(repo, 'build', 'samples');

// A torus of rings x segments quads, two triangles each, as OFF text.
function torusOff(rings, segments, R = 2, r = 0.6) {
  const lines = ['OFF', `${rings * segments} ${2 * rings * segments} 0`];
  for (let i = 0; i < rings; ++i) {
    const u = (2 * Math.PI * i) / rings;
    for (let j = 0; j < segments; ++j) {
      const w = (2 * Math.PI * j) / segments;
      const c = R + r * Math.cos(w);
      lines.push(`${(c * Math.cos(u)).toFixed(6)} ${(c * Math.sin(u)).toFixed(6)} ${(r * Math.sin(w)).toFixed(6)}`);
    }
  }
  const at = (i, j) => (i % rings) * segments + (j % segments);
  for (let i = 0; i < rings; ++i) {
    for (let j = 0; j < segments; ++j) {
      lines.push(`3 ${at(i, j)} ${at(i + 1, j)} ${at(i + 1, j + 1)}`, `3 ${at(i, j)} ${at(i + 1, j + 1)} ${at(i, j + 1)}`);
    }
  }
  return lines.join('\n') + '\n';
}

async function upload(name, body) {
  const r = await fetch(`${v.server.url}/api/v1/meshes?name=${name}`, { method: 'POST', body });
  const text = await r.text();
  assert.equal(r.status, 201, text);
  return JSON.parse(text).id;
}

// Records in the page, every frame, what the viewer shows: the face counts of
// the preview and full mesh hooks, and the progress badge's text (each change).
async function watch() {
  await v.page.evaluate(() => {
    const seen = [];
    window.__bigmeshSeen = seen;
    const tick = () => {
      const h = window.__cgview;
      const stage = document.querySelector('#progress');
      const state = {
        preview: h.lastPreview?.faces ?? null,
        full: h.lastLoaded?.faces ?? null,
        badge: stage && !stage.hidden ? stage.querySelector('.stage').textContent : null,
      };
      const last = seen[seen.length - 1];
      if (!last || last.preview !== state.preview || last.full !== state.full || (state.badge && state.badge !== last.badge)) seen.push(state);
      requestAnimationFrame(tick);
    };
    tick();
  });
}

test('a big mesh shows its preview first, then the full mesh, with the camera unchanged', async () => {
  const rings = 400;
  const segments = 400;
  const faces = 2 * rings * segments;
  const id = await upload('big_torus.off', torusOff(rings, segments));
  await watch();
  await v.page.locator(`#mesh-list li.mesh[data-mesh-id="${id}"]`).click();
  await v.page.waitForFunction((id) => window.__cgview.lastLoaded?.id === id, id, { timeout: 120000 });
  const hooks = await v.page.evaluate(() => ({ preview: window.__cgview.lastPreview, seen: window.__bigmeshSeen, loaded: window.__cgview.lastLoaded }));
  assert.equal(hooks.loaded.faces, faces);
  assert.ok(hooks.preview, `no preview was shown: ${JSON.stringify(hooks.seen)}${v.describeProblems()}`);
  assert.equal(hooks.preview.id, id);
  assert.ok(hooks.preview.faces <= PREVIEW_TARGET && hooks.preview.faces >= PREVIEW_TARGET / 5, `preview faces ${hooks.preview.faces}`);
  // The order the page showed them in: the preview alone (with the badge), then the full mesh.
  const previewAt = hooks.seen.findIndex((s) => s.preview === hooks.preview.faces && s.full === null);
  const fullAt = hooks.seen.findIndex((s) => s.full === faces);
  assert.ok(previewAt >= 0 && fullAt > previewAt, JSON.stringify(hooks.seen));
  // The badge is set with the preview, so the frame that draws the preview
  // shows it; the recorder (a frame callback that may run before the
  // viewer's in that frame) can see it a frame before the preview's hook.
  assert.ok(
    hooks.seen.slice(0, fullAt).some((s) => s.badge && s.badge.includes('preview shown')),
    `no "preview shown" badge: ${JSON.stringify(hooks.seen)}`,
  );
  // The swap kept the camera.
  assert.ok(hooks.preview.fullCamera, 'the full mesh did not replace the preview');
  assert.deepEqual(hooks.preview.fullCamera, hooks.preview.camera);
  // And the full mesh is what is drawn.
  const png = await v.page.locator('#viewport canvas').screenshot();
  fs.mkdirSync(artifactsDir, { recursive: true });
  fs.writeFileSync(path.join(artifactsDir, 'e2e-bigmesh-full.png'), png);
  const { data } = await pngPixels(v.page, png);
  let orange = 0;
  for (let i = 0; i < data.length; i += 4) if (isMeshOrange(data[i], data[i + 1], data[i + 2])) ++orange;
  assert.ok(orange > 1000, `only ${orange} mesh pixels`);
  assert.equal(await v.page.locator('#progress').isHidden(), true);
  assert.deepEqual(v.problems, []);
});

test('a small mesh has no preview', async () => {
  const id = await upload('elephant.off', fs.readFileSync(path.join(samples, 'elephant.off')));
  await v.page.locator(`#mesh-list li.mesh[data-mesh-id="${id}"]`).click();
  await v.page.waitForFunction((id) => window.__cgview.lastLoaded?.id === id, id, { timeout: 60000 });
  const hooks = await v.page.evaluate(() => ({ preview: window.__cgview.lastPreview, loaded: window.__cgview.lastLoaded }));
  assert.equal(hooks.loaded.faces, 5558);
  assert.equal(hooks.preview, null);
  assert.deepEqual(v.problems, []);
});
