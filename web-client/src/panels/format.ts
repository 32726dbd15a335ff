// How the panels write a value from the server (a mesh's report, a job's
// metrics, the skeleton comparison): one rule, so that the same number reads
// the same wherever it is shown. Imports nothing, so that unit tests can load it.

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
