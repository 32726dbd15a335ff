// Unit tests of the panels' one value formatter and its units
// (src/panels/format.ts), used by the report, the job metrics, the skeleton
// comparison and the legends.  `npm run test:unit`.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { importTs } from './ts_module.mjs';

const { formatNumber, formatValue, formatMetric, metricUnit, fieldUnit, withUnit, SIGNIFICANT_DIGITS } = await importTs('panels/format.ts');

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

test("a metric's unit comes from its name: relative, dB, lengths, areas, volumes; counts have none", () => {
  const symbol = (name) => metricUnit(name)?.symbol ?? '';
  // Relative to the bounding box's diagonal (hausdorff, chaos_embed, chaos_encrypt), shown in per cent.
  for (const name of ['hausdorff_relative', 'rms_relative', 'max_displacement_relative', 'key_sensitivity_hausdorff_relative']) {
    assert.equal(symbol(name), '% of diagonal', name);
    assert.equal(metricUnit(name).scale, 100, name);
  }
  // sdf_fast's errors are fractions of the full SDF's range.
  for (const name of ['mean_error', 'p95_error', 'max_error']) assert.equal(symbol(name), '% of range', name);
  assert.equal(symbol('snr_db'), 'dB');
  // Lengths: hausdorff's, a skeleton's, a voxel's, the report's box.
  for (const name of [
    'hausdorff',
    'mesh_to_reference',
    'error_bound',
    'bbox_diagonal',
    'vertex_distance_rms',
    'length',
    'voxel_size',
    'max_distance',
    'bbox min',
    'bbox_max',
    'hausdorff_vertices',
  ])
    assert.equal(symbol(name), 'mesh units', name);
  for (const name of ['area']) assert.equal(symbol(name), 'mesh units²', name);
  for (const name of ['volume', 'volume_before', 'volume_after', 'occupied_volume']) assert.equal(symbol(name), 'mesh units³', name);
  assert.equal(symbol('seconds'), 's');
  assert.equal(symbol('render_cpu_seconds'), 's');
  assert.equal(symbol('speedup'), '×');
  assert.equal(symbol('message_bytes'), 'bytes');
  assert.equal(symbol('memory_mb'), 'MB');
  assert.equal(symbol('capacity_bits_per_vertex'), 'bits/vertex');
  assert.equal(symbol('bits_per_coordinate'), 'bits');
  assert.equal(symbol('inside_fraction'), '%');
  // Counts, flags and ratios without a unit.
  for (const name of [
    'vertices',
    'faces',
    'boundary_loops',
    'genus',
    'euler_characteristic',
    'components',
    'iterations',
    'occupied_voxels',
    'faces_flipped',
    'centredness_mean',
    'centredness_max',
    'round_trip_exact',
    'dim_x',
  ])
    assert.equal(metricUnit(name), null, name);
});

test("a per-element field's unit: lengths and curvatures; relative values stay as fractions; ids and counts have none", () => {
  const symbol = (name) => fieldUnit(name)?.symbol ?? '';
  assert.equal(symbol('distance'), 'mesh units');
  assert.equal(symbol('sdf'), 'mesh units');
  assert.equal(symbol('sdf_fast'), 'mesh units');
  assert.equal(symbol('error'), 'mesh units', "sdf_fast's error field is a difference of SDF values");
  assert.equal(symbol('mean_curvature'), 'mesh units⁻¹');
  assert.equal(symbol('gaussian_curvature'), 'mesh units⁻²');
  assert.equal(symbol('hausdorff_relative'), '× diagonal');
  assert.equal(fieldUnit('hausdorff_relative').scale, 1, 'a field is drawn as it is');
  for (const name of ['sdf_normalized', 'segments', 'branch', 'index', 'votes', 'grid']) assert.equal(fieldUnit(name), null, name);
  assert.equal(withUnit('curvature · mean_curvature', fieldUnit('mean_curvature')), 'curvature · mean_curvature (mesh units⁻¹)');
  assert.equal(withUnit('segments', null), 'segments');
});

test('formatMetric writes the value to four significant digits, scaled and followed by its unit, the exact value in its title', () => {
  assert.deepEqual(formatMetric('hausdorff_relative', 0.0123456), {
    text: '1.235 % of diagonal',
    value: '1.235',
    unit: '% of diagonal',
    title: '0.0123456 — relative: a fraction of the bounding box’s diagonal, shown in per cent',
  });
  assert.equal(formatMetric('hausdorff_relative', 0.0123).text, '1.23 % of diagonal', 'no floating-point tail from the scaling');
  assert.equal(formatMetric('snr_db', 87.654321).text, '87.65 dB');
  assert.equal(formatMetric('area', 1.2453).text, '1.245 mesh units²');
  assert.equal(formatMetric('volume', 0.046201).text, '0.0462 mesh units³');
  assert.equal(formatMetric('bbox_min', [-0.36021, -0.5, -0.30151]).text, '(-0.3602, -0.5, -0.3015) mesh units');
  assert.deepEqual(formatMetric('faces', 5558), { text: '5558', value: '5558', unit: '', title: '' }, 'a count is exact, with no unit and no tooltip');
  assert.equal(formatMetric('message_bytes', 123456).text, '123456 bytes', 'counts of a unit stay exact');
  assert.equal(formatMetric('euler_characteristic', -4).text, '-4');
  assert.equal(formatMetric('closed', true).text, 'yes', 'a boolean has no unit');
  assert.equal(formatMetric('genus', null).text, '—', 'a missing value has no unit');
  assert.equal(formatMetric('vertex_distance_mean', 1.23456e-9).text, '1.235e-9 mesh units');
  assert.equal(formatMetric('centredness_mean', 0.5).title, '', 'a unitless value shown exactly needs no tooltip');
  assert.equal(formatMetric('centredness_mean', 0.123456).title, '0.123456', 'a rounded one gives its exact value');
});
