// Unit tests of which files the upload control sends to POST /data, and as
// what (src/api/data_files.ts).  `npm run test:unit`.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { importTs } from './ts_module.mjs';

const { dataKindOf, needsMesh, DATA_EXTENSIONS } = await importTs('api/data_files.ts');

test('voxel grids, skeletons and text values are data, by extension, in any case', () => {
  for (const name of ['grid.nrrd', 'GRID.NRRD', 'a.binvox', 'a.vti', 'a.vox', 'cloud.vdb']) assert.equal(dataKindOf(name), 'voxel_grid', name);
  for (const name of ['tree.cg', 'tree.polylines', 'tree.polylines.txt', 'Tree.Polylines.TXT']) assert.equal(dataKindOf(name), 'skeleton', name);
  for (const name of ['values.txt', 'sdf.TXT', 'my.polylines.values.txt']) assert.equal(dataKindOf(name), 'scalar_field', name);
});

test('meshes, and the formats both meshes and data come in, stay mesh uploads', () => {
  for (const name of ['a.off', 'a.ply', 'a.obj', 'a.json', 'a.stl', 'a.drc', 'a.glb', 'a.gltf', 'a.zip', 'a.mtl', 'a.png', 'noextension', 'nrrd', 'txt'])
    assert.equal(dataKindOf(name), null, name);
});

test('a field and a skeleton are for the mesh shown; a grid stands alone', () => {
  assert.equal(needsMesh('scalar_field'), true);
  assert.equal(needsMesh('skeleton'), true);
  assert.equal(needsMesh('voxel_grid'), false);
  for (const ext of DATA_EXTENSIONS) assert.notEqual(dataKindOf(`x${ext}`), null, ext);
});
