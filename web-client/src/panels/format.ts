// How the panels write a value from the server (a mesh's report, a job's
// metrics, the skeleton comparison, a legend's range) and what unit it is
// in: one rule, so that the same number reads the same wherever it is shown.
// Imports nothing, so that unit tests can load it (metricCell, the one part
// that needs a document, is not called there).

/** Significant digits of a non-integer: enough to compare, few enough to read. */
export const SIGNIFICANT_DIGITS = 4;

/** An integer as it is ("5558"); any other number to SIGNIFICANT_DIGITS, trailing zeros dropped ("0.1235", "1.5"). */
export function formatNumber(n: number): string {
  if (Number.isInteger(n) || !Number.isFinite(n)) return String(n);
  return Number(n.toPrecision(SIGNIFICANT_DIGITS)).toString();
}

/**
 * Any JSON value as one line of text: numbers by formatNumber, booleans as
 * "yes"/"no", null or a missing value as "—", a list of numbers (a point, a
 * vector) as "(x, y, z)", any other list as "a, b, c", an object as
 * "{key: value, ...}" (braced, so that a list of objects reads unambiguously).
 */
export function formatValue(value: unknown): string {
  if (value === null || value === undefined) return '—';
  if (typeof value === 'number') return formatNumber(value);
  if (typeof value === 'boolean') return value ? 'yes' : 'no';
  if (typeof value === 'string') return value;
  if (Array.isArray(value)) {
    const items = value.map((v) => formatValue(v)).join(', ');
    return value.length > 0 && value.every((v) => typeof v === 'number') ? `(${items})` : items;
  }
  if (typeof value === 'object') {
    const pairs = Object.entries(value as Record<string, unknown>).map(([k, v]) => `${k.replace(/_/g, ' ')}: ${formatValue(v)}`);
    return `{${pairs.join(', ')}}`;
  }
  return String(value);
}

/** A unit: what is written after a value, the factor the value is shown multiplied by, and a sentence for its tooltip. */
export interface Unit {
  symbol: string;
  scale: number;
  meaning: string;
}

export const MESH_UNITS = 'mesh units';

const LENGTH: Unit = { symbol: MESH_UNITS, scale: 1, meaning: 'a length, in the units of the mesh’s coordinates' };
const AREA: Unit = { symbol: `${MESH_UNITS}²`, scale: 1, meaning: 'an area, in the units of the mesh’s coordinates squared' };
const VOLUME: Unit = { symbol: `${MESH_UNITS}³`, scale: 1, meaning: 'a volume, in the units of the mesh’s coordinates cubed' };
const PER_LENGTH: Unit = { symbol: `${MESH_UNITS}⁻¹`, scale: 1, meaning: 'one over a length of the mesh’s units' };
const PER_AREA: Unit = { symbol: `${MESH_UNITS}⁻²`, scale: 1, meaning: 'one over an area of the mesh’s units' };
const OF_DIAGONAL: Unit = { symbol: '% of diagonal', scale: 100, meaning: 'relative: a fraction of the bounding box’s diagonal, shown in per cent' };
const OF_RANGE: Unit = { symbol: '% of range', scale: 100, meaning: 'relative: a fraction of the reference values’ range (max − min), shown in per cent' };
const PERCENT: Unit = { symbol: '%', scale: 100, meaning: 'a share, shown in per cent' };
const DECIBELS: Unit = { symbol: 'dB', scale: 1, meaning: 'decibels: 10 log₁₀ of a ratio of powers' };
const SECONDS: Unit = { symbol: 's', scale: 1, meaning: 'seconds of wall-clock time' };
const TIMES: Unit = { symbol: '×', scale: 1, meaning: 'a ratio' };
const BYTES: Unit = { symbol: 'bytes', scale: 1, meaning: 'a size in bytes' };
const MEGABYTES: Unit = { symbol: 'MB', scale: 1, meaning: 'a size in megabytes' };
const BITS: Unit = { symbol: 'bits', scale: 1, meaning: 'a number of bits' };
const BITS_PER_VERTEX: Unit = { symbol: 'bits/vertex', scale: 1, meaning: 'bits per vertex' };

// The rules, first match wins, on a name in snake_case (a nested report key
// joined with "_": "bbox_min"). The server names a quantity by what it is, so
// its suffix says its unit; names that match none (counts, flags, ids,
// normalized values) are shown bare.
const METRIC_RULES: Array<[RegExp, Unit | null]> = [
  [/_relative$/, OF_DIAGONAL],
  [/(^|_)error$/, OF_RANGE], // sdf_fast's errors, fractions of the full SDF's range
  [/_db$/, DECIBELS],
  [/(^|_)fraction$|(^|_)share$|_changed_(coordinates|faces)$/, PERCENT],
  [/(^|_)seconds$/, SECONDS],
  [/(^|_)speedup$/, TIMES],
  [/(^|_)bytes$/, BYTES],
  [/(^|_)mb$/, MEGABYTES],
  [/_bits_per_vertex$/, BITS_PER_VERTEX],
  [/(^|_)bits$|^bits_per_coordinate$/, BITS],
  [/^centredness_/, null], // a distance divided by the local radius
  [/(^|_)area$/, AREA],
  [/(^|_)volume(_before|_after)?$/, VOLUME],
  [/gaussian_curvature/, PER_AREA],
  [/curvature/, PER_LENGTH],
  [/_normalized$/, null],
  // Bare min, max and mean are sdf's and skeleton_distance's: distances.
  [/hausdorff|distance|diagonal|(^|_)length$|voxel_size|error_bound|mesh_to_reference|reference_to_mesh|^bbox_(min|max|size)$|^(min|max|mean|rms)$/, LENGTH],
  [/^sdf(_vertex|_fast)?$/, LENGTH],
];

/** The unit of a metric or a report entry, from its name; null for a count or anything else without one. */
export function metricUnit(name: string): Unit | null {
  const key = name.toLowerCase().replace(/[\s.]+/g, '_');
  for (const [pattern, unit] of METRIC_RULES) if (pattern.test(key)) return unit;
  return null;
}

/**
 * The unit of a value per element (a scalar field's, a voxel grid's), from
 * the artifact's name. Values per element are drawn as they are, so a
 * relative one reads "× diagonal" rather than in per cent; sdf_fast's
 * `error` field is a plain difference of lengths, unlike its `*_error` metrics.
 */
export function fieldUnit(name: string): Unit | null {
  const key = name.toLowerCase().replace(/[\s.]+/g, '_');
  if (key === 'error') return LENGTH;
  const unit = metricUnit(key);
  if (unit === OF_DIAGONAL) return { ...unit, symbol: '× diagonal', scale: 1 };
  if (unit === OF_RANGE || unit === PERCENT) return null;
  return unit;
}

function scaled(value: unknown, scale: number): unknown {
  if (scale === 1) return value;
  if (typeof value === 'number') return value * scale;
  if (Array.isArray(value)) return value.map((v) => scaled(v, scale));
  return value;
}

/**
 * A named value as shown in a table: `text` is the value by formatValue,
 * scaled by its unit and followed by it ("1.235 % of diagonal", "0.0462 mesh
 * units³", "5558"); `unit` is the unit's symbol ('' when it has none);
 * `title` says what the unit means and gives the value exactly as sent.
 */
export function formatMetric(name: string, value: unknown): { text: string; value: string; unit: string; title: string } {
  const numeric = typeof value === 'number' || (Array.isArray(value) && value.length > 0 && value.every((v) => typeof v === 'number'));
  const unit = numeric ? metricUnit(name) : null;
  const shown = formatValue(scaled(value, unit?.scale ?? 1));
  const exact = numeric ? JSON.stringify(value) : '';
  if (!unit) return { text: shown, value: shown, unit: '', title: exact !== shown ? exact : '' };
  return { text: `${shown} ${unit.symbol}`, value: shown, unit: unit.symbol, title: `${exact} — ${unit.meaning}` };
}

/**
 * A table cell of a named value (the report's, a metrics table's): the
 * number, then its unit in a muted span; formatMetric's title as its tooltip.
 */
export function metricCell(name: string, value: unknown, className = ''): HTMLTableCellElement {
  const { value: shown, unit, title } = formatMetric(name, value);
  const td = document.createElement('td');
  if (className) td.className = className;
  if (title) td.title = title;
  td.append(shown);
  if (unit) {
    const span = document.createElement('span');
    span.className = 'unit';
    span.textContent = ` ${unit}`;
    td.append(span);
  }
  return td;
}

/** A legend's or a slider's heading: the name and, in brackets, the unit of its values ("distance (mesh units)"). */
export function withUnit(label: string, unit: Unit | null): string {
  return unit ? `${label} (${unit.symbol})` : label;
}
