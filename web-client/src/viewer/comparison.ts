// Scalar fields side by side (a comparison): each field on the same surface in
// its own pane of the viewer, all drawn through the one camera (viewer.ts
// says why), each with its own title, colour map and legend with histogram.
// "One range per hint" colours the fields of one hint (an exact quantity and
// its approximation, say) over their common range, so that equal values get
// equal colours across panes; each field keeps its own range otherwise.
// Whatever algorithms made the fields: this is the scalar-field renderer
// repeated per pane, nothing in it knows one algorithm from another.
import { el } from '../panels/dom.ts';
import { defaultMapFor } from './colormaps.ts';
import { Legend } from './legend.ts';
import type { PlyMesh } from './ply.ts';
import { buildScalarSurface, colourGeometry, type ScalarField } from './scalar_field_renderer.ts';
import { paneGrid, type Viewer } from './viewer.ts';
import type * as THREE from 'three';

export interface ComparedField {
  /** Identifies the field across show() calls (a chosen colour map is kept): `${jobId}/${artifact}`. */
  key: string;
  title: string;
  data: ScalarField;
  /** The artifact's ColorHint: it chooses the default colour map. */
  hint?: string;
}

export class ComparisonView {
  private readonly viewer: Viewer;
  private readonly container: HTMLElement;
  /** Called after each frame that changed what the panes show, with each pane's key, colour map and range. */
  private readonly onDrawn: (panes: Array<{ key: string; map: string; range: [number, number] }>) => void;
  private root: HTMLElement | null = null;
  private legends: Legend[] = [];
  private panes: Array<{ field: ComparedField; object: THREE.Mesh }> = [];
  /** Colour maps chosen in a pane's legend, by key. */
  private readonly maps = new Map<string, string>();
  /** Whether the fields of one hint share their common range (kept across comparisons). */
  private sameRange = false;

  constructor(viewer: Viewer, container: HTMLElement, onDrawn: ComparisonView['onDrawn']) {
    this.viewer = viewer;
    this.container = container;
    this.onDrawn = onDrawn;
  }

  /** Panes of prepared objects (showObjects), beside the field panes. */
  private objectPanes = 0;

  get active(): boolean {
    return this.panes.length > 0 || this.objectPanes > 0;
  }

  /**
   * Shows prepared objects side by side (a skeleton over the plain surface in
   * each pane, say), each under a title with an optional colour swatch;
   * replaces any comparison.  The same panes, camera and way back as fields.
   * With `owned` false the objects are already shown (the scene's): drawn
   * in the panes, and left shown, not disposed, when the comparison ends.
   */
  showObjects(items: Array<{ key: string; title: string; object: THREE.Object3D; color?: string }>, owned = true): void {
    this.removeOverlay();
    this.panes = [];
    const { cols, rows } = paneGrid(items.length);
    const cells = items.map((it, i) =>
      el(
        'div',
        { class: 'compare-pane', 'data-pane': String(i), 'data-key': it.key },
        el('div', { class: 'legend compare-title' }, ...(it.color ? [el('span', { class: 'swatch', style: `background:${it.color}` }), ' '] : []), it.title),
      ),
    );
    this.root = el('div', { class: 'compare-view', style: `grid-template-columns: repeat(${cols}, 1fr); grid-template-rows: repeat(${rows}, 1fr)` }, ...cells);
    this.container.append(this.root);
    this.objectPanes = items.length;
    const drawn = () => this.onDrawn(items.map((it) => ({ key: it.key, map: '', range: [0, 0] as [number, number] })));
    this.viewer.setPanes(
      items.map((it) => it.object),
      drawn,
      owned,
    );
  }

  /** Shows `fields` (one value per vertex or per face of `mesh`, server order) side by side, replacing any comparison. */
  show(mesh: PlyMesh, fields: ComparedField[]): void {
    this.removeOverlay();
    const { cols, rows } = paneGrid(fields.length);
    const cells = fields.map((f, i) => el('div', { class: 'compare-pane', 'data-pane': String(i), 'data-key': f.key }));
    const same = el('input', { type: 'checkbox', class: 'compare-same-range' });
    same.checked = this.sameRange;
    same.addEventListener('change', () => {
      this.sameRange = same.checked;
      this.panes.forEach((_, i) => this.recolour(i));
      this.redraw();
    });
    const options = el('label', { class: 'compare-options', title: 'Colour the fields of one hint over their common range' }, same, ' One range per hint');
    this.root = el('div', { class: 'compare-view', style: `grid-template-columns: repeat(${cols}, 1fr); grid-template-rows: repeat(${rows}, 1fr)` }, ...cells, options);
    this.container.append(this.root);
    this.panes = fields.map((field) => ({ field, object: buildScalarSurface(mesh, field.data, this.mapOf(field)) }));
    this.legends = cells.map((cell, i) => new Legend(cell, (name) => this.setMap(i, name)));
    this.panes.forEach((_, i) => this.recolour(i));
    this.viewer.setPanes(
      this.panes.map((p) => p.object),
      () => this.drawn(),
    );
  }

  /** Ends the comparison: the panes are disposed and the viewer shows one view again. */
  clear(): void {
    if (!this.active) return;
    this.removeOverlay();
    this.panes = [];
    this.objectPanes = 0;
    this.viewer.setPanes([]);
  }

  private mapOf(field: ComparedField): string {
    return this.maps.get(field.key) ?? defaultMapFor(field.hint);
  }

  /** The field as pane `i` colours it: over the common range of its hint's fields with "One range per hint". */
  private shown(i: number): ScalarField {
    const { data, hint } = this.panes[i]!.field;
    if (!this.sameRange || hint === 'categorical') return data;
    const ranges = this.panes.filter((p) => p.field.hint === hint).map((p) => p.field.data.range);
    return { ...data, range: [Math.min(...ranges.map((r) => r[0])), Math.max(...ranges.map((r) => r[1]))] };
  }

  private setMap(i: number, name: string): void {
    if (!this.panes[i]) return;
    this.maps.set(this.panes[i].field.key, name);
    this.recolour(i);
    this.redraw();
  }

  /** Colours pane `i` and its legend by its map over its range. */
  private recolour(i: number): void {
    const { field, object } = this.panes[i]!;
    const data = this.shown(i);
    const map = this.mapOf(field);
    colourGeometry(object.geometry, data, map);
    this.legends[i]!.show(field.title, data.range, map, data.values);
    this.root?.children[i]?.setAttribute('data-map', map);
  }

  private redraw(): void {
    const panes = this.panes;
    this.viewer.redraw(() => {
      if (this.panes === panes) this.drawn();
    });
  }

  private drawn(): void {
    this.onDrawn(this.panes.map((p, i) => ({ key: p.field.key, map: this.mapOf(p.field), range: this.shown(i).range })));
  }

  private removeOverlay(): void {
    for (const l of this.legends) l.dispose();
    this.legends = [];
    this.root?.remove();
    this.root = null;
  }
}
