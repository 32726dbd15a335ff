// Unit tests of the application state's store (src/state/store.ts): a
// subscriber is called exactly when the part it selected changes.
// `npm run test:unit`.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { importTs } from './ts_module.mjs';

const { Store, shallowEqual } = await importTs('state/store.ts');

const initial = () => ({ meshes: [], selectedId: null, jobs: new Map(), scene: [], picked: 0 });

test('a subscriber fires when its slice changes, and only then', () => {
  const store = new Store(initial());
  const seen = [];
  store.subscribe(
    (s) => s.selectedId,
    (value, previous) => seen.push([value, previous]),
  );
  store.update({ picked: 1 });
  store.update({ jobs: new Map() });
  assert.deepEqual(seen, [], 'other slices changed');
  store.update({ selectedId: 'a' });
  store.update({ selectedId: 'a' });
  store.update((s) => ({ selectedId: s.selectedId }));
  assert.deepEqual(seen, [['a', null]], 'set once, then set to the same value twice');
  store.update((s) => ({ selectedId: s.selectedId + 'b' }));
  assert.deepEqual(seen, [
    ['a', null],
    ['ab', 'a'],
  ]);
  assert.equal(store.get().selectedId, 'ab');
  assert.equal(store.get().picked, 1, 'an update keeps the fields it does not name');
});

test('a selector of several slices compares them one by one', () => {
  const store = new Store(initial());
  const meshes = [{ id: 'a' }];
  let calls = 0;
  store.subscribe(
    (s) => [s.meshes, s.selectedId, s.scene.map((e) => e.mesh).join(' ')],
    () => ++calls,
  );
  store.update({ meshes });
  assert.equal(calls, 1);
  store.update({ meshes, picked: 3 });
  assert.equal(calls, 1, 'the same list, another slice');
  store.update({ scene: [{ mesh: 'a' }] });
  assert.equal(calls, 2);
  store.update({ scene: [{ mesh: 'a' }] });
  assert.equal(calls, 2, 'a new scene of the same meshes');
  store.update({ meshes: [...meshes] });
  assert.equal(calls, 3, 'a new list (compared by identity)');
});

test('a custom equality, a first call on request, and unsubscribing', () => {
  const store = new Store(initial());
  const ids = [];
  const stop = store.subscribe(
    (s) => s.meshes,
    (m) => ids.push(m.map((x) => x.id).join()),
    {
      equals: (a, b) => a.map((x) => x.id).join() === b.map((x) => x.id).join(),
      now: true,
    },
  );
  assert.deepEqual(ids, ['']);
  store.update({ meshes: [{ id: 'a' }] });
  store.update({ meshes: [{ id: 'a' }] });
  assert.deepEqual(ids, ['', 'a']);
  stop();
  store.update({ meshes: [{ id: 'b' }] });
  assert.deepEqual(ids, ['', 'a']);
});

test('a subscriber that updates is served first; later ones see each change once', () => {
  const store = new Store(initial());
  const order = [];
  store.subscribe(
    (s) => s.selectedId,
    (id) => {
      order.push(`select ${id}`);
      store.update({ picked: 0, scene: [{ mesh: id }] });
    },
  );
  store.subscribe(
    (s) => s.scene,
    (scene) => order.push(`scene ${scene.map((e) => e.mesh).join()}`),
  );
  store.subscribe(
    (s) => s.selectedId,
    (id) => order.push(`list ${id}`),
  );
  store.update({ selectedId: 'a' });
  assert.deepEqual(order, ['select a', 'scene a', 'list a']);
  order.length = 0;
  store.update({ picked: 2 });
  assert.deepEqual(order, []);
});

test('a subscriber removed by an earlier one is not called', () => {
  const store = new Store(initial());
  let stopSecond = () => {};
  let second = 0;
  store.subscribe(
    (s) => s.picked,
    () => stopSecond(),
  );
  stopSecond = store.subscribe(
    (s) => s.picked,
    () => ++second,
  );
  store.update({ picked: 1 });
  assert.equal(second, 0);
});

test('shallowEqual: one level deep', () => {
  assert.equal(shallowEqual([1, 'a', null], [1, 'a', null]), true);
  assert.equal(shallowEqual([1, {}], [1, {}]), false);
  assert.equal(shallowEqual({ a: 1, b: 'x' }, { b: 'x', a: 1 }), true);
  assert.equal(shallowEqual({ a: 1 }, { a: 1, b: undefined }), false);
  assert.equal(shallowEqual(new Map(), new Map()), false);
  assert.equal(shallowEqual(NaN, NaN), true);
  assert.equal(shallowEqual(null, undefined), false);
});
