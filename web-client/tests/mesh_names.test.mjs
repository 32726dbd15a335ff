// Unit tests of how the mesh list tells meshes of one name apart
// (src/panels/mesh_names.ts).  `npm run test:unit`.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { importTs } from './ts_module.mjs';

const { repeatedNameTags } = await importTs('panels/mesh_names.ts');

const mesh = (id, name, created) => ({ id, name, created, format: 'off', bytes: 1, report: {} });
const UTC = 'UTC';

test('a name of its own gets no tag', () => {
  const tags = repeatedNameTags([mesh('a1', 'bunny.off', '2026-11-28T16:20:00Z'), mesh('b2', 'kitten.off', '2026-11-28T16:20:00Z')], UTC);
  assert.equal(tags.size, 0);
});

test('two uploads of one name are told apart by their upload time', () => {
  const tags = repeatedNameTags(
    [mesh('a1aaaaaaaa', 'bunny.off', '2026-11-28T09:05:00Z'), mesh('b2bbbbbbbb', 'bunny.off', '2026-11-28T16:20:30Z'), mesh('c3', 'kitten.off', '2026-11-28T16:20:30Z')],
    UTC,
  );
  assert.deepEqual([...tags.keys()].sort(), ['a1aaaaaaaa', 'b2bbbbbbbb']);
  assert.match(tags.get('a1aaaaaaaa'), /^09:05$/);
  assert.match(tags.get('b2bbbbbbbb'), /^16:20$/);
});

test('uploads of one name within the same minute are told apart by their id', () => {
  const tags = repeatedNameTags([mesh('a1aaaaaaaa', 'bunny.off', '2026-11-28T16:20:01Z'), mesh('b2bbbbbbbb', 'bunny.off', '2026-11-28T16:20:40Z')], UTC);
  assert.equal(tags.get('a1aaaaaaaa'), '16:20 · a1aaaa');
  assert.equal(tags.get('b2bbbbbbbb'), '16:20 · b2bbbb');
  assert.notEqual(tags.get('a1aaaaaaaa'), tags.get('b2bbbbbbbb'));
});

test('uploads of one name on different days name the day; an unreadable time leaves the id', () => {
  const tags = repeatedNameTags([mesh('a1aaaaaaaa', 'bunny.off', '2026-11-27T16:20:00Z'), mesh('b2bbbbbbbb', 'bunny.off', '2026-11-28T16:20:00Z')], UTC);
  assert.match(tags.get('a1aaaaaaaa'), /27.*16:20/);
  assert.match(tags.get('b2bbbbbbbb'), /28.*16:20/);
  const odd = repeatedNameTags([mesh('a1aaaaaaaa', 'x.off', 'not a time'), mesh('b2bbbbbbbb', 'x.off', 'not a time')], UTC);
  assert.deepEqual([...odd.values()], ['a1aaaa', 'b2bbbb']);
});

test('three of one name: each tag differs from the others', () => {
  const meshes = [mesh('a1aaaaaaaa', 'm.off', '2026-11-28T16:20:00Z'), mesh('b2bbbbbbbb', 'm.off', '2026-11-28T16:20:10Z'), mesh('c3cccccccc', 'm.off', '2026-11-28T17:00:00Z')];
  const tags = repeatedNameTags(meshes, UTC);
  assert.equal(new Set(tags.values()).size, 3, JSON.stringify([...tags]));
  assert.equal(tags.get('c3cccccccc'), '17:00', 'a time of its own needs no id');
});
