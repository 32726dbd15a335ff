// Unit tests of a live lecture's pure parts: the view as a lecture's parts
// and back (src/viewer/view_state.ts), and a recording's state at a moment
// (src/controllers/replay.ts).  `npm run test:unit`.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { importTs } from './ts_module.mjs';

const { viewParts, viewFromParts, VIEW_PARTS } = await importTs('viewer/view_state.ts');
const { stateAt } = await importTs('controllers/replay.ts');

const camera = { position: [1, 2, 3], target: [0, 0.5, 0], up: [0, 1, 0], fov: 40 };

test('a whole view goes into the parts and comes back the same', () => {
  const view = {
    state: {
      v: 1,
      mesh: 'm1',
      camera,
      display: { mode: 'flat' },
      overlays: { axes: true },
      field: { job: 'j1', artifact: 'distance', map: 'viridis', range: [0, 2] },
      scene: [
        { mesh: 'm1', visible: true },
        { mesh: 'job:j2/mesh', visible: false },
      ],
      panes: true,
    },
    up: 'z',
    compare: ['j1/distance', 'j3/other'],
    show: ['j4/skeleton'],
  };
  const parts = viewParts(view);
  assert.deepEqual(Object.keys(parts).sort(), [...VIEW_PARTS].sort());
  assert.deepEqual(parts.camera, camera);
  // What the server shares with the followers is named as `mesh` and `job`.
  assert.deepEqual(parts.meshes.jobs, ['j2']);
  assert.deepEqual(parts.meshes.compare, [
    { job: 'j1', artifact: 'distance' },
    { job: 'j3', artifact: 'other' },
  ]);
  assert.deepEqual(parts.skeletons, [{ job: 'j4', artifact: 'skeleton' }]);
  assert.deepEqual(viewFromParts(JSON.parse(JSON.stringify(parts))), view);
});

test('a plain view: no field, no scene, nothing shown beside it', () => {
  const view = { state: { v: 1, mesh: 'm1', camera, display: { mode: 'smooth' }, overlays: {} }, up: 'y', compare: [], show: [] };
  const parts = viewParts(view);
  assert.equal(parts.field, null);
  assert.equal(parts.meshes.scene, undefined);
  assert.deepEqual(viewFromParts(JSON.parse(JSON.stringify(parts))), view);
});

test('parts without a mesh or a camera hold no view yet; a bad one says what is wrong', () => {
  assert.equal(viewFromParts({}), null);
  assert.equal(viewFromParts({ camera }), null);
  assert.equal(viewFromParts({ meshes: { mesh: 'm1' } }), null);
  assert.throws(() => viewFromParts({ meshes: { mesh: 'm1' }, camera: { ...camera, fov: 400 } }), /fov/);
  assert.throws(() => viewFromParts({ meshes: { mesh: 'm1' }, camera, skeletons: ['j4/skeleton'] }), /skeletons must be a list of \{job, artifact\}/);
});

test("a recording's state at a moment: each part's latest value by then", () => {
  const events = [
    { t_ms: 0, part: 'meshes', value: { mesh: 'm1' } },
    { t_ms: 5, part: 'camera', value: 1 },
    { t_ms: 40, part: 'camera', value: 2 },
    { t_ms: 40, part: 'field', value: { job: 'j1' } },
    { t_ms: 90, part: 'field', value: null },
  ];
  assert.deepEqual(stateAt(events, -1), { state: {}, next: 0 });
  assert.deepEqual(stateAt(events, 39), { state: { meshes: { mesh: 'm1' }, camera: 1 }, next: 2 });
  assert.deepEqual(stateAt(events, 40), { state: { meshes: { mesh: 'm1' }, camera: 2, field: { job: 'j1' } }, next: 4 });
  assert.deepEqual(stateAt(events, 1e9).state.field, null);
});
