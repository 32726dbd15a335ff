// The Display panel's rows: checkboxes, sliders with their value beside them.
import { EDGE_COLORS } from '../viewer/overlays.ts';
import { el } from './dom.ts';

export function checkbox(id: string, text: string): { row: HTMLLabelElement; input: HTMLInputElement } {
  const input = el('input', { type: 'checkbox', id });
  return { row: el('label', { class: 'display-check' }, input, ` ${text}`), input };
}

export function slider(id: string, min: number, max: number, step: number): HTMLInputElement {
  return el('input', { type: 'range', id, min: String(min), max: String(max), step: String(step) });
}

export function row(text: string, control: HTMLElement): HTMLLabelElement {
  return el('label', { class: 'display-row' }, el('span', {}, text), control);
}

/**
 * A slider's row with its value written beside it. The slider is named by
 * `text` alone (aria-label), so that its name does not change with the value.
 */
export function sliderRow(text: string, input: HTMLInputElement, value: HTMLOutputElement): HTMLLabelElement {
  input.setAttribute('aria-label', text);
  value.htmlFor.add(input.id);
  return row(text, el('span', { class: 'slider-with-value' }, input, value));
}

/** What the edge overlay's colours mean. */
export function edgeLegend(): HTMLDivElement {
  return el(
    'div',
    { class: 'display-edge-legend' },
    el('span', { style: `color:${EDGE_COLORS.boundary}` }, '■ boundary'),
    ' ',
    el('span', { style: `color:${EDGE_COLORS.nonManifold}` }, '■ non-manifold'),
  );
}
