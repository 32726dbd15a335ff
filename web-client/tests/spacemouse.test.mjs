// Unit test of src/viewer/spacemouse.ts: 3D-mouse input reports as WebHID
// hands them over (the report id apart, six int16 little-endian axes), and
// the camera motion they make.  `npm run test:unit`.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { importTs } from './ts_module.mjs';

const M = await importTs('viewer/spacemouse.ts');

function report(...values) {
  const v = new DataView(new ArrayBuffer(2 * values.length));
  values.forEach((x, i) => v.setInt16(2 * i, x, true));
  return v;
}

test('older devices: translation in report 1, rotation in report 2', () => {
  // Constructed as a SpaceNavigator (046d:c626) sends it: the cap pushed right and pressed a little.
  const bytes = new Uint8Array([0x5e, 0x01, 0x00, 0x00, 0x28, 0x00]);
  const t = M.parseSpaceMouseReport(1, new DataView(bytes.buffer));
  assert.deepEqual(t.translation, [350 / 350, 0, 40 / 350]);
  assert.equal(t.rotation, null);
  const r = M.parseSpaceMouseReport(2, report(-175, 0, 350));
  assert.deepEqual(r.rotation, [-0.5, 0, 1]);
  assert.equal(r.translation, null);
});

test('newer devices: all six axes in report 1', () => {
  const r = M.parseSpaceMouseReport(1, report(35, -70, 0, 0, 0, -350));
  assert.deepEqual(r.translation, [0.1, -0.2, 0]);
  assert.deepEqual(r.rotation, [0, 0, -1]);
});

test('buttons, unknown and short reports', () => {
  assert.equal(M.parseSpaceMouseReport(3, new DataView(new Uint8Array([3, 0]).buffer)).buttons, 3);
  assert.equal(M.parseSpaceMouseReport(4, report(1, 2, 3)), null);
  assert.equal(M.parseSpaceMouseReport(2, report(1, 2)), null);
  assert.deepEqual(M.SPACEMOUSE_VENDORS, [0x256f, 0x046d]);
});

test('camera motion: push away moves forward, twist yaws, small values are dead', () => {
  const m = M.cameraMotion([0.5, -1, 0.01], [0, 0, 0.5]);
  assert.equal(m.right, 0.5);
  assert.equal(m.forward, 1);
  assert.equal(m.up, -0); // under the dead zone
  assert.equal(m.yaw, -0.75);
  assert.equal(m.pitch, -0);
});
