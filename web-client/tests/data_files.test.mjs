// Unit tests of which files the upload control sends to POST /data, and as
// what, and of which mesh files go up together as one zip
// (src/api/data_files.ts).  `npm run test:unit`.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { importTs } from './ts_module.mjs';

const { dataKindOf, groupUploads, needsMesh, DATA_EXTENSIONS } = await importTs('api/data_files.ts');

test('voxel grids, skeletons and text values are data, by extension, in any case', () => {
  for (const name of ['grid.nrrd', 'GRID.NRRD', 'a.binvox', 'a.vti', 'a.vox', 'cloud.vdb']) assert.equal(dataKindOf(name), 'voxel_grid', name);
  for (const name of ['tree.cg', 'tree.polylines', 'tree.polylines.txt', 'Tree.Polylines.TXT']) assert.equal(dataKindOf(name), 'skeleton', name);
  for (const name of ['values.txt', 'sdf.TXT', 'my.polylines.values.txt']) assert.equal(dataKindOf(name), 'scalar_field', name);
});

test('meshes, and the formats both meshes and data come in, stay mesh uploads', () => {
  for (const name of ['a.off', 'a.ply', 'a.obj', 'a.json', 'a.stl', 'a.drc', 'a.glb', 'a.gltf', 'a.zip', 'a.mtl', 'a.bin', 'a.png', 'noextension', 'nrrd', 'txt'])
    assert.equal(dataKindOf(name), null, name);
});

test('a field and a skeleton are for the mesh shown; a grid stands alone', () => {
  assert.equal(needsMesh('scalar_field'), true);
  assert.equal(needsMesh('skeleton'), true);
  assert.equal(needsMesh('voxel_grid'), false);
  for (const ext of DATA_EXTENSIONS) assert.notEqual(dataKindOf(`x${ext}`), null, ext);
});

test('an OBJ with its MTL and images is one upload; meshes chosen alone go alone', () => {
  assert.deepEqual(groupUploads(['cow.obj', 'cow.mtl', 'cow.png']), { groups: [{ mesh: 'cow.obj', companions: ['cow.mtl', 'cow.png'] }], problems: [] });
  assert.deepEqual(groupUploads(['a.off', 'b.ply']), {
    groups: [
      { mesh: 'a.off', companions: [] },
      { mesh: 'b.ply', companions: [] },
    ],
    problems: [],
  });
  // A zip is a bundle already.
  assert.deepEqual(groupUploads(['cow.zip']).groups, [{ mesh: 'cow.zip', companions: [] }]);
});

test('a .gltf with its .bin and images is one upload, the .gltf the mesh; the .bin is never a mesh of its own', () => {
  assert.deepEqual(groupUploads(['duck.gltf', 'duck.bin', 'DuckCM.png', 'normal.JPG']), {
    groups: [{ mesh: 'duck.gltf', companions: ['duck.bin', 'DuckCM.png', 'normal.JPG'] }],
    problems: [],
  });
  // In any order, any case, a buffer named otherwise than the .gltf.
  assert.deepEqual(groupUploads(['buffer0.BIN', 'Scene.GLTF']).groups, [{ mesh: 'Scene.GLTF', companions: ['buffer0.BIN'] }]);
  // An OBJ chosen beside takes its MTL, not the buffer; the .gltf takes no MTL.
  assert.deepEqual(groupUploads(['cow.obj', 'cow.mtl', 'duck.gltf', 'duck.bin']).groups, [
    { mesh: 'cow.obj', companions: ['cow.mtl'] },
    { mesh: 'duck.gltf', companions: ['duck.bin'] },
  ]);
  // Two glTFs: each its own buffer by name; one named after neither goes with both.
  assert.deepEqual(groupUploads(['a.gltf', 'b.gltf', 'b.bin', 'a.bin', 'shared.bin']).groups, [
    { mesh: 'a.gltf', companions: ['a.bin', 'shared.bin'] },
    { mesh: 'b.gltf', companions: ['b.bin', 'shared.bin'] },
  ]);
});

test('a .bin without its .gltf is not uploaded, and the problem says why; the rest still goes up', () => {
  const lone = groupUploads(['duck.bin']);
  assert.deepEqual(lone.groups, []);
  assert.equal(lone.problems.length, 1);
  assert.match(lone.problems[0], /duck\.bin.*\.gltf/);
  const beside = groupUploads(['elephant.off', 'duck.bin', 'duck.png']);
  assert.deepEqual(beside.groups, [{ mesh: 'elephant.off', companions: ['duck.png'] }]);
  assert.equal(beside.problems.length, 1);
  assert.match(beside.problems[0], /duck\.bin/);
  // Materials and images alone: no mesh to go with.
  const images = groupUploads(['cow.mtl', 'cow.png']);
  assert.deepEqual(images.groups, []);
  assert.match(images.problems.join(' '), /cow\.mtl, cow\.png: choose the mesh file/);
});
