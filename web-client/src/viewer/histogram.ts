// The histogram of a scalar field's values, drawn under its legend. Pure (no
// DOM, no three.js), so that node's unit tests load it as it is.

/**
 * Counts the finite values in `bins` equal bins over [lo, hi]; values outside
 * the range go to the first or last bin (the colours clamp the same way).
 */
export function histogram(values: Float32Array, [lo, hi]: [number, number], bins: number): { counts: Uint32Array; total: number } {
  const counts = new Uint32Array(bins);
  let total = 0;
  const scale = hi > lo ? bins / (hi - lo) : 0;
  for (const v of values) {
    if (!Number.isFinite(v)) continue;
    const b = scale ? Math.floor((v - lo) * scale) : bins >> 1;
    ++counts[Math.min(bins - 1, Math.max(0, b))]!;
    ++total;
  }
  return { counts, total };
}

/**
 * The values at the `lo` and `hi` percentiles (0..100) of the finite values,
 * by nearest rank: the range that clips the tails of a field (1 and 99 drop
 * the extreme 1% on each side). [0, 0] when no value is finite.
 */
export function percentileRange(values: Float32Array, lo: number, hi: number): [number, number] {
  const finite = values.filter((v) => Number.isFinite(v)).sort();
  if (!finite.length) return [0, 0];
  const rank = (p: number) => finite[Math.min(finite.length - 1, Math.max(0, Math.round((p / 100) * (finite.length - 1))))]!;
  return [rank(lo), rank(hi)];
}
