// Unit tests of src/viewer/colormaps.ts (turbo, the map of each hint) and
// src/viewer/histogram.ts (the legend's bins). `npm run test:unit`.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { importTs } from './ts_module.mjs';

const { colorMap, defaultMapFor, sample } = await importTs('viewer/colormaps.ts');
const { histogram } = await importTs('viewer/histogram.ts');

test('each hint has its map: magnitude (distances, errors) is turbo', () => {
  assert.equal(defaultMapFor('magnitude'), 'turbo');
  assert.equal(defaultMapFor('symmetric'), 'coolwarm');
  assert.equal(defaultMapFor('categorical'), 'tab10');
  assert.equal(defaultMapFor('standard'), 'viridis');
  assert.equal(defaultMapFor(undefined), 'viridis');
});

test('turbo goes from blue for the lowest value, through green, to red for the highest', () => {
  const turbo = colorMap('turbo');
  assert.equal(turbo.name, 'turbo');
  const at = (t) => {
    const rgb = [0, 0, 0];
    sample(turbo, t, 0, 1, rgb);
    return rgb;
  };
  const [r0, g0, b0] = at(0.1);
  assert.ok(b0 > r0 && b0 > g0, `blue near the bottom: ${at(0.1)}`);
  const [r5, g5, b5] = at(0.5);
  assert.ok(g5 > r5 && g5 > b5, `green in the middle: ${at(0.5)}`);
  const [r1, g1, b1] = at(1);
  assert.ok(r1 > 0.4 && r1 > 4 * g1 && r1 > 4 * b1, `red at the top: ${at(1)}`);
  for (const c of turbo.stops) assert.match(c, /^#[0-9a-f]{6}$/);
});

test('the histogram counts every finite value once, clamping to the range', () => {
  const values = Float32Array.from([0, 0.1, 0.5, 0.99, 1, NaN, Infinity, -3, 7]);
  const { counts, total } = histogram(values, [0, 1], 4);
  assert.deepEqual([...counts], [3, 0, 1, 3]); // -3 with 0 and 0.1 in the first bin; 1 and 7 with 0.99 in the last
  assert.equal(total, 7);
  const flat = histogram(Float32Array.from([2, 2, 2]), [2, 2], 5);
  assert.deepEqual([...flat.counts], [0, 0, 3, 0, 0], 'an empty range puts everything in the middle bin');
});
