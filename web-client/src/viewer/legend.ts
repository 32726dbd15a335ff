// The colour-map legend over the viewport: the field's name, a gradient bar,
// its min and max, and a select to change the colour map.
import { COLOR_MAPS, colorMap, cssGradient } from './colormaps.ts';

function formatValue(v: number): string {
  if (v === 0) return '0';
  const a = Math.abs(v);
  if (a >= 1e5 || a < 1e-3) return v.toExponential(3);
  return Number(v.toPrecision(4)).toString();
}

export class Legend {
  private readonly root: HTMLElement;
  private readonly title: HTMLElement;
  private readonly bar: HTMLElement;
  private readonly min: HTMLElement;
  private readonly max: HTMLElement;
  private readonly select: HTMLSelectElement;

  constructor(container: HTMLElement, onMapChange: (name: string) => void) {
    this.root = document.createElement('div');
    this.root.className = 'legend';
    this.root.id = 'legend';
    this.root.hidden = true;
    this.title = document.createElement('div');
    this.title.className = 'legend-title';
    this.select = document.createElement('select');
    this.select.className = 'legend-map';
    this.select.setAttribute('aria-label', 'Colour map');
    for (const m of COLOR_MAPS) {
      const o = document.createElement('option');
      o.value = m.name;
      o.textContent = m.name;
      this.select.append(o);
    }
    this.select.addEventListener('change', () => onMapChange(this.select.value));
    const head = document.createElement('div');
    head.className = 'legend-head';
    head.append(this.title, this.select);
    this.bar = document.createElement('div');
    this.bar.className = 'legend-bar';
    const labels = document.createElement('div');
    labels.className = 'legend-labels';
    this.min = document.createElement('span');
    this.min.className = 'legend-min';
    this.max = document.createElement('span');
    this.max.className = 'legend-max';
    labels.append(this.min, this.max);
    this.root.append(head, this.bar, labels);
    container.append(this.root);
  }

  show(title: string, range: [number, number], mapName: string): void {
    const map = colorMap(mapName);
    this.title.textContent = title;
    this.title.title = title;
    this.select.value = map.name;
    this.bar.style.background = cssGradient(map);
    this.min.textContent = formatValue(range[0]);
    this.max.textContent = formatValue(range[1]);
    this.root.dataset.map = map.name;
    this.root.hidden = false;
  }

  hide(): void {
    this.root.hidden = true;
  }
}
