// Unit tests of the panels' one value formatter (src/panels/format.ts), used
// by the report, the job metrics and the skeleton comparison.  `npm run test:unit`.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { importTs } from './ts_module.mjs';

const { formatNumber, formatValue, SIGNIFICANT_DIGITS } = await importTs('panels/format.ts');

test('integers are written whole, other numbers to four significant digits', () => {
  assert.equal(SIGNIFICANT_DIGITS, 4);
  assert.equal(formatNumber(5558), '5558');
  assert.equal(formatNumber(1234567), '1234567');
  assert.equal(formatNumber(0), '0');
  assert.equal(formatNumber(-3), '-3');
  assert.equal(formatNumber(0.123456), '0.1235');
  assert.equal(formatNumber(-2.71828), '-2.718');
  assert.equal(formatNumber(1.5), '1.5', 'no trailing zeros');
  assert.equal(formatNumber(1234.5678), '1235');
  assert.equal(formatNumber(0.000123456), '0.0001235');
  assert.equal(formatNumber(1.23456e-9), '1.235e-9');
  assert.equal(formatNumber(Number.NaN), 'NaN');
  assert.equal(formatNumber(Infinity), 'Infinity');
});

test('a non-integer has at most four significant digits, within 5e-4 relative of it, over many magnitudes', () => {
  for (let e = -8; e <= 8; ++e) {
    for (const m of [1.00049, 3.14159265, 9.87654321]) {
      const v = m * 10 ** e;
      if (Number.isInteger(v)) continue; // written whole
      const shown = Number(formatNumber(v));
      assert.ok(Math.abs(shown - v) <= 5e-4 * v, `${v} shown as ${formatNumber(v)}`);
      assert.ok(
        formatNumber(v)
          .replace(/e.*$/, '')
          .replace(/[-.]/g, '')
          .replace(/^0+|0+$/g, '').length <= 4,
        `${v} shown as ${formatNumber(v)}`,
      );
    }
  }
});

test('booleans, missing values and strings', () => {
  assert.equal(formatValue(true), 'yes');
  assert.equal(formatValue(false), 'no');
  assert.equal(formatValue(null), '—');
  assert.equal(formatValue(undefined), '—');
  assert.equal(formatValue('closed'), 'closed');
  assert.equal(formatValue(''), '');
  assert.equal(formatValue(0.666666), '0.6667', 'a number value goes through formatNumber');
  assert.equal(formatValue(42), '42');
});

test('a list of numbers is a tuple, any other list is comma-separated', () => {
  assert.equal(formatValue([-0.5, 0.123456, 2]), '(-0.5, 0.1235, 2)');
  assert.equal(formatValue(['a', 'b', 'c']), 'a, b, c');
  assert.equal(formatValue([1, 'x', null, true]), '1, x, —, yes');
  assert.equal(
    formatValue([
      [0, 0, 0],
      [1.23456, 2, 3],
    ]),
    '(0, 0, 0), (1.235, 2, 3)',
  );
  assert.equal(formatValue([]), '');
});

test('an object is braced key: value pairs, its numbers rounded the same way', () => {
  assert.equal(formatValue({ mean_edge: 0.0123456, count: 7 }), '{mean edge: 0.01235, count: 7}');
  assert.equal(formatValue({}), '{}');
  assert.equal(
    formatValue([
      { a: 1, b: 2 },
      { a: 3, b: 4 },
    ]),
    '{a: 1, b: 2}, {a: 3, b: 4}',
  );
});
