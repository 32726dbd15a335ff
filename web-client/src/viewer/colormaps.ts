// Colour maps for scalar fields: matplotlib's viridis, magma and inferno
// (sequential), Google's turbo (sequential, blue for low to red for high: the
// default for magnitudes such as distances and errors), coolwarm (diverging,
// for fields symmetric around zero) and tab10 (categorical labels). Sequential and diverging maps are stops at
// equal spacing, interpolated linearly in sRGB; the categorical one picks a
// colour per integer value.

export interface ColorMap {
  name: string;
  /** sRGB stops, equally spaced over 0..1. */
  stops: readonly string[];
  /** Categorical: value v gets stops[v mod n], no interpolation. */
  categorical?: boolean;
}

/**
 * Turbo (Mikhailov, Google AI blog, 2019) from its published polynomial
 * approximation, sampled at `n` equal steps: dark blue, cyan, green, yellow,
 * orange, dark red.
 */
function turboStops(n: number): string[] {
  const poly = [
    [0.13572138, 4.6153926, -42.66032258, 132.13108234, -152.94239396, 59.28637943],
    [0.09140261, 2.19418839, 4.84296658, -14.18503333, 4.27729857, 2.82956604],
    [0.1066733, 12.64194608, -60.58204836, 110.36276771, -89.90310912, 27.34824973],
  ];
  const stops: string[] = [];
  for (let i = 0; i < n; ++i) {
    const x = i / (n - 1);
    const channel = (c: number[]) => {
      const v = c.reduceRight((acc, k) => acc * x + k, 0);
      return Math.round(255 * Math.min(1, Math.max(0, v)));
    };
    stops.push(`#${poly.map((c) => channel(c).toString(16).padStart(2, '0')).join('')}`);
  }
  return stops;
}

export const COLOR_MAPS: readonly ColorMap[] = [
  {
    name: 'viridis',
    stops: ['#440154', '#482475', '#414487', '#355f8d', '#2a788e', '#21918c', '#22a884', '#44bf70', '#7ad151', '#bddf26', '#fde725'],
  },
  {
    name: 'magma',
    stops: ['#000004', '#140e36', '#3b0f70', '#641a80', '#8c2981', '#b73779', '#de4968', '#f7705c', '#fe9f6d', '#fecf92', '#fcfdbf'],
  },
  {
    name: 'inferno',
    stops: ['#000004', '#160b39', '#420a68', '#6a176e', '#932667', '#bc3754', '#dd513a', '#f37819', '#fca50a', '#f6d746', '#fcffa4'],
  },
  { name: 'turbo', stops: turboStops(33) },
  {
    name: 'coolwarm',
    stops: ['#3b4cc0', '#6282ea', '#8db0fe', '#b8d0f9', '#dddddd', '#f5c4ac', '#f49a7b', '#de604d', '#b40426'],
  },
  {
    name: 'tab10',
    stops: ['#1f77b4', '#ff7f0e', '#2ca02c', '#d62728', '#9467bd', '#8c564b', '#e377c2', '#7f7f7f', '#bcbd22', '#17becf'],
    categorical: true,
  },
];

export function colorMap(name: string): ColorMap {
  return COLOR_MAPS.find((m) => m.name === name) ?? COLOR_MAPS[0]!;
}

/** The map a field's hint asks for (ScalarField's ColorHint: standard, symmetric, magnitude, categorical). */
export function defaultMapFor(hint: string | undefined): string {
  if (hint === 'symmetric') return 'coolwarm';
  if (hint === 'categorical') return 'tab10';
  if (hint === 'magnitude') return 'turbo';
  return 'viridis';
}

function parseHex(hex: string): [number, number, number] {
  const n = parseInt(hex.slice(1), 16);
  return [((n >> 16) & 255) / 255, ((n >> 8) & 255) / 255, (n & 255) / 255];
}

const parsed = new Map<string, Array<[number, number, number]>>();

function rgbStops(map: ColorMap): Array<[number, number, number]> {
  let s = parsed.get(map.name);
  if (!s) {
    s = map.stops.map(parseHex);
    parsed.set(map.name, s);
  }
  return s;
}

/**
 * The sRGB colour (0..1 channels) of `value` on `map` over [lo, hi]. NaN and
 * infinite values get a neutral grey; an empty range maps to the middle.
 */
export function sample(map: ColorMap, value: number, lo: number, hi: number, out: [number, number, number]): void {
  if (!Number.isFinite(value)) {
    out[0] = out[1] = out[2] = 0.5;
    return;
  }
  const stops = rgbStops(map);
  if (map.categorical) {
    const n = stops.length;
    const c = stops[((Math.round(value) % n) + n) % n]!;
    out[0] = c[0];
    out[1] = c[1];
    out[2] = c[2];
    return;
  }
  let t = hi > lo ? (value - lo) / (hi - lo) : 0.5;
  t = Math.min(1, Math.max(0, t)) * (stops.length - 1);
  const i = Math.min(stops.length - 2, Math.floor(t));
  const f = t - i;
  const a = stops[i]!;
  const b = stops[i + 1]!;
  out[0] = a[0] + (b[0] - a[0]) * f;
  out[1] = a[1] + (b[1] - a[1]) * f;
  out[2] = a[2] + (b[2] - a[2]) * f;
}

/** A CSS linear-gradient (left to right) showing the map, for the legend. */
export function cssGradient(map: ColorMap): string {
  const n = map.stops.length;
  if (map.categorical) {
    const parts = map.stops.map((c, i) => `${c} ${(i / n) * 100}% ${((i + 1) / n) * 100}%`);
    return `linear-gradient(to right, ${parts.join(', ')})`;
  }
  const parts = map.stops.map((c, i) => `${c} ${(i / (n - 1)) * 100}%`);
  return `linear-gradient(to right, ${parts.join(', ')})`;
}
