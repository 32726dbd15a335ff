// Unit test of src/api/voxel_slice.ts (the voxel-slice payload of
// protocol/API.md): a payload built here by the documented layout, with
// node's zlib, decoded by the viewer's code.  `npm run test:unit`.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import zlib from 'node:zlib';
import { importTs } from './ts_module.mjs';

const { decodeSlicePayload } = await importTs('api/voxel_slice.ts');

function payload({ axis, type, index, width, height, values }) {
  const raw = type === 2 ? Buffer.from(new Float32Array(values).buffer) : Buffer.from(Uint8Array.from(values));
  const packed = zlib.deflateSync(raw);
  const head = Buffer.alloc(64);
  head.write('CGVS', 0, 'latin1');
  head.writeUInt16LE(1, 4);
  head.writeUInt8(axis, 6);
  head.writeUInt8(type, 7);
  head.writeUInt32LE(index, 8);
  head.writeUInt32LE(width, 12);
  head.writeUInt32LE(height, 16);
  head.writeUInt32LE(1, 20);
  head.writeUInt32LE(raw.length, 24);
  head.writeUInt32LE(packed.length, 28);
  head.writeDoubleLE(0.5, 32);
  head.writeDoubleLE(1, 40);
  head.writeDoubleLE(2, 48);
  head.writeDoubleLE(4, 56);
  return new Uint8Array(Buffer.concat([head, packed]));
}

test('a uint8 slice decodes by the documented layout', async () => {
  const values = Array.from({ length: 30 }, (_, i) => i % 7);
  const s = await decodeSlicePayload(payload({ axis: 2, type: 1, index: 3, width: 6, height: 5, values }));
  assert.equal(s.axis, 'z');
  assert.equal(s.index, 3);
  assert.equal(s.width, 6);
  assert.equal(s.height, 5);
  assert.equal(s.voxelSize, 0.5);
  assert.deepEqual(s.corner, [1, 2, 4]);
  assert.ok(s.values instanceof Uint8Array);
  assert.deepEqual(Array.from(s.values), values);
});

test('a float slice decodes as float32', async () => {
  const values = [0, 0.25, -1.5, 3];
  const s = await decodeSlicePayload(payload({ axis: 0, type: 2, index: 0, width: 2, height: 2, values }));
  assert.equal(s.axis, 'x');
  assert.ok(s.values instanceof Float32Array);
  assert.deepEqual(Array.from(s.values), values);
});

test('malformed payloads are rejected', async () => {
  await assert.rejects(decodeSlicePayload(new Uint8Array(10)));
  const p = payload({ axis: 2, type: 1, index: 0, width: 2, height: 2, values: [1, 0, 1, 0] });
  const wrongMagic = p.slice();
  wrongMagic[0] = 0x58;
  await assert.rejects(decodeSlicePayload(wrongMagic), /magic/);
  const wrongWidth = p.slice();
  wrongWidth[12] = 9;
  await assert.rejects(decodeSlicePayload(wrongWidth), /inconsistent/);
});
