// Unit tests of src/viewer/draco_geometry.ts, what the Draco worker decodes:
// a point cloud made here with draco3d's own encoder (positions, normals and
// 8-bit colours, as the server streams an uploaded cloud or a job's points)
// comes back as points with every value it was given; a triangle mesh
// (draco3d's bunny) still comes back as one; a stream of neither is refused.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import fs from 'node:fs';
import { createRequire } from 'node:module';
import draco3d from 'draco3d';
import { importTs } from './ts_module.mjs';

const { decodeDraco } = await importTs('viewer/draco_geometry.ts');
const decoder = await draco3d.createDecoderModule({});
const encoder = await draco3d.createEncoderModule({});

/** A Draco point cloud of `positions` (and normals and RGB colours when given), positions quantized to `bits`. */
function encodeCloud(positions, normals, colors, bits = 14) {
  const builder = new encoder.PointCloudBuilder();
  const cloud = new encoder.PointCloud();
  const n = positions.length / 3;
  builder.AddFloatAttribute(cloud, encoder.POSITION, n, 3, positions);
  if (normals) builder.AddFloatAttribute(cloud, encoder.NORMAL, n, 3, normals);
  if (colors) builder.AddUInt8Attribute(cloud, encoder.COLOR, n, 3, colors);
  const e = new encoder.Encoder();
  e.SetAttributeQuantization(encoder.POSITION, bits);
  e.SetAttributeQuantization(encoder.NORMAL, 12);
  // The sequential method keeps the points in the order given, so they can be compared one by one.
  e.SetEncodingMethod(encoder.POINT_CLOUD_SEQUENTIAL_ENCODING);
  const out = new encoder.DracoInt8Array();
  const bytes = e.EncodePointCloudToDracoBuffer(cloud, false, out);
  assert.ok(bytes > 0, 'draco3d encoded the cloud');
  const payload = new Int8Array(bytes);
  for (let i = 0; i < bytes; ++i) payload[i] = out.GetValue(i);
  for (const o of [out, e, cloud, builder]) encoder.destroy(o);
  return payload.buffer;
}

/** `n` points on the unit sphere (a Fibonacci spiral), their normals, and a colour per point from its position. */
function sphere(n) {
  const positions = new Float32Array(3 * n);
  const colors = new Uint8Array(3 * n);
  for (let i = 0; i < n; ++i) {
    const y = 1 - (2 * (i + 0.5)) / n;
    const r = Math.sqrt(1 - y * y);
    const phi = i * Math.PI * (3 - Math.sqrt(5));
    positions.set([r * Math.cos(phi), y, r * Math.sin(phi)], 3 * i);
    colors.set([(i * 7) % 256, (i * 13) % 256, (i * 29) % 256], 3 * i);
  }
  return { positions, normals: positions.slice(), colors };
}

test('a Draco point cloud decodes to its points, normals and colours, with no faces', () => {
  const n = 1000;
  const { positions, normals, colors } = sphere(n);
  const cloud = decodeDraco(decoder, encodeCloud(positions, normals, colors));
  assert.equal(cloud.points, true);
  assert.equal(cloud.vertices, n);
  assert.equal(cloud.faces, 0);
  assert.equal(cloud.indices.length, 0);
  assert.equal(cloud.positions.length, 3 * n);
  // 14 bits over a box 2 wide: a step of 2 / 16383; the worst error is half of it.
  const step = 2 / ((1 << 14) - 1);
  let worst = 0;
  for (let i = 0; i < 3 * n; ++i) worst = Math.max(worst, Math.abs(cloud.positions[i] - positions[i]));
  assert.ok(worst <= step, `positions within one quantization step (${worst} > ${step})`);
  assert.ok(cloud.normals, 'the normals are decoded');
  let angle = 0;
  for (let i = 0; i < n; ++i) {
    const dot = cloud.normals[3 * i] * normals[3 * i] + cloud.normals[3 * i + 1] * normals[3 * i + 1] + cloud.normals[3 * i + 2] * normals[3 * i + 2];
    angle = Math.max(angle, Math.acos(Math.min(1, dot)));
  }
  assert.ok(angle < 0.01, `normals within 0.01 rad (${angle})`);
  assert.ok(cloud.colors, 'the colours are decoded');
  assert.equal(cloud.colors.itemSize, 3);
  assert.equal(cloud.colors.normalized, true);
  assert.ok(cloud.colors.array instanceof Uint8Array);
  assert.deepEqual([...cloud.colors.array], [...colors]);
  assert.equal(cloud.uvs, null);
  assert.equal(cloud.groups, null);
});

test('a point cloud of positions only has no normals and no colours', () => {
  const { positions } = sphere(50);
  const cloud = decodeDraco(decoder, encodeCloud(positions, null, null));
  assert.equal(cloud.points, true);
  assert.equal(cloud.vertices, 50);
  assert.equal(cloud.normals, null);
  assert.equal(cloud.colors, null);
});

test('a triangle mesh still decodes as one', () => {
  const require = createRequire(import.meta.url);
  const bunny = fs.readFileSync(require.resolve('draco3d/bunny.drc'));
  const mesh = decodeDraco(decoder, bunny.buffer.slice(bunny.byteOffset, bunny.byteOffset + bunny.byteLength));
  assert.equal(mesh.points, false);
  assert.ok(mesh.faces > 0);
  assert.equal(mesh.indices.length, 3 * mesh.faces);
  assert.ok(mesh.indices.every((i) => i < mesh.vertices));
});

test('a stream that is no Draco geometry is refused with what it is not', () => {
  assert.throws(() => decodeDraco(decoder, new Uint8Array([1, 2, 3, 4, 5, 6, 7, 8]).buffer), /neither a triangle mesh nor a point cloud/);
});
