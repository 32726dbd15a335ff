// Unit tests of the scene's pure parts: the objects of a view link's scene
// checked (src/viewer/scene_state.ts) and the link's scene and panes read
// back (src/viewer/view_state.ts).  `npm run test:unit`.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { importTs } from './ts_module.mjs';

const { sanitizeScene, sanitizeSceneObject, defaultSceneObject, isIdentity, sceneColor, SCENE_COLORS, MAX_SCENE_OBJECTS } = await importTs('viewer/scene_state.ts');
const { decodeViewHash, encodeViewHash } = await importTs('viewer/view_state.ts');

const camera = { position: [0, 0, 3], target: [0, 0, 0], up: [0, 1, 0], fov: 40 };

test('a valid object is taken as given', () => {
  const o = { mesh: 'm2', visible: false, color: '#20C040', position: [4, -1, 0.5], rotation: [0, 90, -45], scale: 0.5 };
  assert.deepEqual(sanitizeSceneObject(o), { ...o, color: '#20c040' });
});

test('invalid fields fall back to the defaults, and out-of-range ones are clamped', () => {
  const o = sanitizeSceneObject({ mesh: 'm', visible: 'yes', color: 'red', position: [1, 2], rotation: [720, -720, 'x'], scale: -2 });
  assert.deepEqual(o, defaultSceneObject('m'));
  const c = sanitizeSceneObject({ mesh: 'm', rotation: [720, -720, 10], scale: 1e9, position: [1e9, 0, 0] });
  assert.deepEqual(c.rotation, [360, -360, 10]);
  assert.equal(c.scale, 1000);
  assert.deepEqual(c.position, [1e6, 0, 0]);
  assert.equal(sanitizeSceneObject({ visible: true }), null);
  assert.equal(sanitizeSceneObject([1]), null);
});

test('a scene must be a list of objects that name a mesh; a long one is cut', () => {
  assert.throws(() => sanitizeScene({ mesh: 'a' }), /not a list/);
  assert.throws(() => sanitizeScene([{ mesh: 'a' }, { color: '#ffffff' }]), /needs a mesh id/);
  const many = Array.from({ length: MAX_SCENE_OBJECTS + 5 }, (_, i) => ({ mesh: `m${i}` }));
  assert.equal(sanitizeScene(many).length, MAX_SCENE_OBJECTS);
});

test('identity transforms, and colours given in turn', () => {
  assert.equal(isIdentity(defaultSceneObject('a')), true);
  assert.equal(isIdentity({ ...defaultSceneObject('a'), rotation: [0, 0, 1] }), false);
  assert.equal(sceneColor(0), SCENE_COLORS[0]);
  assert.equal(sceneColor(SCENE_COLORS.length), SCENE_COLORS[0]);
  assert.notEqual(sceneColor(1), sceneColor(0));
});

test('a view link holds the scene and its panes; an old link without them still reads', () => {
  const scene = [
    { mesh: 'a', visible: true, color: null, position: [0, 0, 0], rotation: [0, 0, 30], scale: 0.75 },
    { mesh: 'b', visible: false, color: '#3f8fe0', position: [4, 0, 0], rotation: [0, 0, 0], scale: 1 },
  ];
  const state = { v: 1, mesh: 'a', camera, scene, panes: true };
  assert.deepEqual(decodeViewHash(encodeViewHash(state)), state);
  const old = decodeViewHash(encodeViewHash({ v: 1, mesh: 'a', camera }));
  assert.equal(old.scene, undefined);
  assert.equal(old.panes, undefined);
});

test('a view link whose scene does not begin with its mesh, or names none, is refused', () => {
  assert.throws(() => decodeViewHash(encodeViewHash({ v: 1, mesh: 'a', camera, scene: [{ mesh: 'b' }] })), /begin with its mesh/);
  assert.throws(() => decodeViewHash(encodeViewHash({ v: 1, mesh: 'a', camera, scene: [] })), /begin with its mesh/);
  assert.throws(() => decodeViewHash(encodeViewHash({ v: 1, mesh: 'a', camera, scene: [{ mesh: 'a' }, 3] })), /each name a mesh/);
  assert.throws(() => decodeViewHash(encodeViewHash({ v: 1, mesh: 'a', camera, panes: 'yes' })), /panes/);
});
