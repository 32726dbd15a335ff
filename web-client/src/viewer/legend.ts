// The colour-map legend of a scalar field: its name, a select to change the
// colour map, a gradient bar with the range's min and max, and under the bar
// a histogram of the values over the same range (bars coloured by the map).
// The histogram is SVG, one <rect> per bin, so that it scales with the legend
// and tests can read its bins (data-bins, data-total) from the DOM.
import { COLOR_MAPS, colorMap, cssGradient, sample } from './colormaps.ts';
import { histogram } from './histogram.ts';
import { el } from '../panels/dom.ts';
import { formatNumber } from '../panels/format.ts';

/** Bins of the legend's histogram. */
export const HISTOGRAM_BINS = 48;

const SVG = 'http://www.w3.org/2000/svg';

export class Legend {
  private readonly root: HTMLElement;
  private readonly title = el('div', { class: 'legend-title' });
  private readonly bar = el('div', { class: 'legend-bar' });
  private readonly min = el('span', { class: 'legend-min' });
  private readonly max = el('span', { class: 'legend-max' });
  private readonly select = el('select', { class: 'legend-map', 'aria-label': 'Colour map' });
  private readonly histogram = document.createElementNS(SVG, 'svg');

  /** `id`: the element's id (the main view's legend is #legend). */
  constructor(container: HTMLElement, onMapChange: (name: string) => void, id?: string) {
    for (const m of COLOR_MAPS) this.select.append(el('option', { value: m.name }, m.name));
    this.select.addEventListener('change', () => onMapChange(this.select.value));
    this.histogram.classList.add('legend-histogram');
    this.histogram.setAttribute('preserveAspectRatio', 'none');
    this.root = el(
      'div',
      { class: 'legend', id },
      el('div', { class: 'legend-head' }, this.title, this.select),
      this.bar,
      el('div', { class: 'legend-labels' }, this.min, this.max),
      this.histogram,
    );
    this.root.hidden = true;
    container.append(this.root);
  }

  /** Shows the legend of `values` coloured on `mapName` over `range`. */
  show(title: string, range: [number, number], mapName: string, values: Float32Array): void {
    const map = colorMap(mapName);
    this.title.textContent = title;
    this.title.title = title;
    this.select.value = map.name;
    this.bar.style.background = cssGradient(map);
    this.min.textContent = formatNumber(range[0]);
    this.max.textContent = formatNumber(range[1]);
    this.root.dataset.map = map.name;
    this.drawHistogram(values, range, map.name);
    this.root.hidden = false;
  }

  hide(): void {
    this.root.hidden = true;
  }

  /** Removes the legend from the page. */
  dispose(): void {
    this.root.remove();
  }

  private drawHistogram(values: Float32Array, range: [number, number], mapName: string): void {
    const map = colorMap(mapName);
    const { counts, total } = histogram(values, range, HISTOGRAM_BINS);
    const peak = Math.max(1, ...counts);
    const rgb: [number, number, number] = [0, 0, 0];
    const bars = [...counts].map((n, i) => {
      sample(map, range[0] + ((i + 0.5) / HISTOGRAM_BINS) * (range[1] - range[0]), range[0], range[1], rgb);
      const rect = document.createElementNS(SVG, 'rect');
      const h = n / peak;
      for (const [k, v] of Object.entries({ x: i, y: 1 - h, width: 1, height: h })) rect.setAttribute(k, String(v));
      rect.setAttribute('fill', `rgb(${rgb.map((c) => Math.round(255 * c)).join(',')})`);
      rect.dataset.count = String(n);
      return rect;
    });
    this.histogram.setAttribute('viewBox', `0 0 ${HISTOGRAM_BINS} 1`);
    this.histogram.dataset.bins = String(HISTOGRAM_BINS);
    this.histogram.dataset.total = String(total);
    this.histogram.replaceChildren(...bars);
  }
}
