// Scalar fields side by side (a comparison): each field on the same surface in
// its own pane of the viewer, all drawn through the one camera (viewer.ts
// says why), each with its own title, colour map and legend with histogram.
// "One range per hint" colours the fields of one hint (an exact quantity and
// its approximation, say) over their common range, so that equal values get
// equal colours across panes; each field keeps its own range otherwise.
// Whatever algorithms made the fields: this is the scalar-field renderer
// repeated per pane, nothing in it knows one algorithm from another.
//
// "Fit each pane": objects of very different sizes (a 1-unit part beside a
// 1000-unit assembly) framed together leave the small one a dot. Then each
// pane is drawn from its own camera: the one camera moved, for that pane's
// draw only, by the similarity that takes the framed sphere to the bounding
// sphere of the pane's object (same direction, distance scaled), so that
// orbiting and zooming still move every pane alike. It is done in the
// scene's onBeforeRender, which three calls at the start of each pane's
// render, before the camera's matrices are read; onAfterRender puts the
// camera back.
import * as THREE from 'three';
import { el } from '../panels/dom.ts';
import { clipPlanes } from './clipping.ts';
import { defaultMapFor } from './colormaps.ts';
import { frameBox } from './framing.ts';
import { Legend } from './legend.ts';
import type { PlyMesh } from './ply.ts';
import { buildScalarSurface, colourGeometry, type ScalarField } from './scalar_field_renderer.ts';
import { paneGrid, type Viewer } from './viewer.ts';

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
  /** The objects in the panes, in pane order. */
  private paneObjects: THREE.Object3D[] = [];
  /** With "Fit each pane": the sphere the one camera is framed on, which each pane's object stands in for. */
  private fitted: THREE.Sphere | null = null;
  /** The one camera as the frame set it, while a pane is drawn from its own. */
  private saved: { position: THREE.Vector3; near: number; far: number } | null = null;
  private fitButton: HTMLButtonElement | null = null;

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
    this.root = el('div', { class: 'compare-view', style: `grid-template-columns: repeat(${cols}, 1fr); grid-template-rows: repeat(${rows}, 1fr)` }, ...cells, this.options());
    this.container.append(this.root);
    this.objectPanes = items.length;
    this.paneObjects = items.map((it) => it.object);
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
    this.paneObjects = this.panes.map((p) => p.object);
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
    this.paneObjects = [];
    this.viewer.setPanes([]);
  }

  /** The bar under panes of different objects (fields are all on one surface: one framing fits them all). */
  private options(): HTMLElement {
    const fit = el(
      'button',
      { type: 'button', class: 'button small compare-fit', 'aria-pressed': 'false', title: 'Frame each pane on its own object (objects of very different sizes)' },
      'Fit each pane',
    );
    fit.addEventListener('click', () => this.fitEach(!this.fitted));
    this.fitButton = fit;
    return el('div', { class: 'compare-options' }, fit);
  }

  /** Frames each pane on its own object (on), or all of them together again (off). */
  fitEach(on: boolean): void {
    const scene = this.viewer.scene;
    if (on) {
      const first = this.paneObjects[0];
      const box = first ? new THREE.Box3().setFromObject(first) : new THREE.Box3();
      if (box.isEmpty()) return;
      frameBox(this.viewer.camera, this.viewer.controls, box);
      this.fitted = box.getBoundingSphere(new THREE.Sphere());
      scene.onBeforeRender = (renderer) => this.paneCamera(renderer);
      scene.onAfterRender = () => this.restoreCamera();
    } else {
      if (!this.fitted) return;
      this.endFitEach();
      this.viewer.fitAll();
    }
    this.fitButton?.setAttribute('aria-pressed', String(on));
    this.viewer.requestRender();
  }

  private endFitEach(): void {
    if (!this.fitted) return;
    this.fitted = null;
    const scene = this.viewer.scene;
    scene.onBeforeRender = THREE.Object3D.prototype.onBeforeRender;
    scene.onAfterRender = THREE.Object3D.prototype.onAfterRender;
  }

  /** Before a pane's render: the camera framing that pane's object as the one camera frames the fitted sphere. */
  private paneCamera(renderer: THREE.WebGLRenderer): void {
    const fitted = this.fitted;
    if (!fitted) return;
    const viewport = renderer.getViewport(new THREE.Vector4());
    let i = 0;
    for (let r = this.viewer.paneRect(0); r; r = this.viewer.paneRect(++i)) {
      if (r.x === viewport.x && r.y === viewport.y && r.width === viewport.z && r.height === viewport.w) break;
    }
    const object = this.paneObjects[i];
    if (!object) return;
    const box = new THREE.Box3().setFromObject(object);
    if (box.isEmpty()) return;
    const sphere = box.getBoundingSphere(new THREE.Sphere());
    const k = Math.max(sphere.radius, 1e-9) / Math.max(fitted.radius, 1e-9);
    const camera = this.viewer.camera;
    this.saved = { position: camera.position.clone(), near: camera.near, far: camera.far };
    const target = this.viewer.controls.target.clone().sub(fitted.center).multiplyScalar(k).add(sphere.center);
    camera.position.sub(fitted.center).multiplyScalar(k).add(sphere.center);
    camera.updateMatrixWorld(true); // its lights ride with it
    const forward = camera.getWorldDirection(new THREE.Vector3());
    const { near, far } = clipPlanes(camera.position.toArray(), forward.toArray(), box.min.toArray(), box.max.toArray(), camera.position.distanceTo(target));
    camera.near = near;
    camera.far = far;
    camera.updateProjectionMatrix();
  }

  private restoreCamera(): void {
    const saved = this.saved;
    if (!saved) return;
    this.saved = null;
    const camera = this.viewer.camera;
    camera.position.copy(saved.position);
    camera.near = saved.near;
    camera.far = saved.far;
    camera.updateProjectionMatrix();
    camera.updateMatrixWorld(true);
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

  /** Takes the panes' overlay away; the panes that follow are framed together until asked otherwise. */
  private removeOverlay(): void {
    this.endFitEach();
    this.fitButton = null;
    for (const l of this.legends) l.dispose();
    this.legends = [];
    this.root?.remove();
    this.root = null;
  }
}
