// The selection tool over the viewer: click to pick a face or vertex, drag a
// box or a lasso, with Shift to add and Ctrl (or Cmd) to subtract; grow,
// shrink, invert and clear; the selection drawn over the surface.
//
// It works on the mesh in the server's order (viewer/ply.ts: the ids are the
// stored mesh's), not on the Draco-decoded surface on screen, whose
// Edgebreaker coder reorders faces and vertices; both are the same surface
// up to Draco's quantization.
//
// Visible only (the default): a face is selected when its centroid projects
// into the region and the face shows at one pixel at least of the region in
// an id buffer (each face drawn in its own colour, depth-tested, off screen,
// through the viewer's camera); a vertex when it projects into the region
// and one of its faces shows there. Through: every face or vertex that
// projects into the region, hidden ones too (MeshLab's default). A click
// reads the id buffer at the pixel: the face drawn there; for a vertex, the
// corner of that face nearest the pointer.
//
// The stored positions are the mesh's own coordinates; the shown object may
// be turned (Z up) or moved (the Scene panel's Move/Turn), so they are
// projected, drawn in the id buffer and highlighted through its matrixWorld.
import * as THREE from 'three';
import type { PlyMesh } from './ply.ts';
import { idMesh } from './id_mesh.ts';
import { highlight } from './selection_highlight.ts';
import {
  combine,
  faceCentroids,
  facesArea,
  growShrink,
  invert,
  pointsInRegion,
  projectPoints,
  regionBounds,
  vertexFaces,
  type Adjacency,
  type Combine,
  type Region,
  type SelectionKind,
} from './selection.ts';
import type { Viewer } from './viewer.ts';

export type SelectionShape = 'box' | 'lasso';

export interface SelectionState {
  meshId: string | null;
  /** False while the mesh in the server's order is being fetched (nothing can be selected yet). */
  ready: boolean;
  kind: SelectionKind;
  ids: number[];
  /** The total area of the selected faces (faces only). */
  area: number | null;
  /** Why nothing can be selected on this mesh (a point cloud has no faces to pick through), or null. */
  refused: string | null;
}

/** Picking goes through an id buffer of faces: a cloud has none. */
const CLOUD_REFUSAL = 'A point cloud has no faces: selections are of a mesh’s faces and vertices.';

interface Target {
  meshId: string;
  ply: PlyMesh;
  centroids: Float32Array;
  around: Adjacency;
  /** The id buffer's geometry (built at the first use). */
  idMesh: THREE.Mesh | null;
}

export class SelectionTool {
  active = false;
  shape: SelectionShape = 'box';
  through = false;
  private kindNow: SelectionKind = 'faces';
  private target: Target | null = null;
  /** Why the mesh selected on cannot be selected on (see SelectionState.refused). */
  private refused: string | null = null;
  private ids: number[] = [];
  private readonly viewer: Viewer;
  private readonly svg: SVGSVGElement;
  private readonly path: SVGPolygonElement;
  private readonly onChange: (state: SelectionState) => void;
  private readonly setNavigation: (enabled: boolean) => void;
  /** The mesh to select on and how to fetch it in the server's order (fetched when the tool is first used). */
  private source: { meshId: string; load: (id: string) => Promise<PlyMesh> } | null = null;
  private drag: { points: number[]; how: Combine; id: number } | null = null;
  private renderTarget: THREE.WebGLRenderTarget | null = null;
  private readonly idScene = new THREE.Scene();

  constructor(viewer: Viewer, container: HTMLElement, onChange: (state: SelectionState) => void, setNavigation: (enabled: boolean) => void) {
    this.viewer = viewer;
    this.onChange = onChange;
    this.setNavigation = setNavigation;
    const ns = 'http://www.w3.org/2000/svg';
    this.svg = document.createElementNS(ns, 'svg');
    this.svg.classList.add('selection-region');
    this.path = document.createElementNS(ns, 'polygon');
    this.svg.append(this.path);
    container.append(this.svg);
    const canvas = viewer.renderer.domElement;
    canvas.addEventListener('pointerdown', (e) => this.down(e));
    canvas.addEventListener('pointermove', (e) => this.move(e));
    canvas.addEventListener('pointerup', (e) => this.up(e));
    canvas.addEventListener('pointercancel', () => this.endDrag());
  }

  get kind(): SelectionKind {
    return this.kindNow;
  }

  state(): SelectionState {
    const t = this.target;
    return {
      meshId: this.source?.meshId ?? null,
      ready: t !== null && t.meshId === this.source?.meshId,
      kind: this.kindNow,
      ids: this.ids,
      area: t && this.kindNow === 'faces' ? facesArea(t.ply.positions, t.ply.indices, this.ids) : null,
      refused: this.refused,
    };
  }

  /**
   * The mesh to select on, or null; `load` fetches it in the server's order,
   * when the tool is first turned on (or now, when it is on). The selection is cleared.
   */
  setSource(meshId: string | null, load: (id: string) => Promise<PlyMesh>): void {
    if (meshId === this.source?.meshId) return;
    this.source = meshId ? { meshId, load } : null;
    this.setMesh(null, null);
    if (this.active) this.fetch();
  }

  private fetch(): void {
    const source = this.source;
    if (!source || this.target?.meshId === source.meshId) return;
    source.load(source.meshId).then(
      (ply) => {
        if (this.source === source) this.setMesh(source.meshId, ply);
      },
      () => {},
    );
  }

  private setMesh(meshId: string | null, ply: PlyMesh | null): void {
    if (this.target?.idMesh) this.target.idMesh.geometry.dispose();
    this.idScene.clear();
    this.refused = ply && ply.faces === 0 ? CLOUD_REFUSAL : null;
    if (this.refused) ply = null;
    this.target = meshId && ply ? { meshId, ply, centroids: faceCentroids(ply.positions, ply.indices), around: vertexFaces(ply.indices, ply.vertices), idMesh: null } : null;
    this.set([]);
  }

  /** The vertex count of the mesh selected on (in the server's order), or null before it is fetched. */
  get vertexCount(): number | null {
    return this.target?.ply.vertices ?? null;
  }

  /** Turns the tool on (the camera stays put: the navigation is off) or off. */
  setActive(on: boolean): void {
    this.active = on;
    this.setNavigation(!on);
    if (on) this.fetch();
    this.viewer.renderer.domElement.classList.toggle('selecting', on);
    if (!on) this.endDrag();
  }

  setKind(kind: SelectionKind): void {
    if (kind === this.kindNow) return;
    this.kindNow = kind;
    this.set([]);
  }

  clear(): void {
    this.set([]);
  }

  /** Selects exactly `ids`, of the kind now (a cleared selection given back). */
  select(ids: readonly number[]): void {
    if (this.target) this.set([...ids]);
  }

  /**
   * Shows a selection of the mesh selected on (a lecture's presenter's): the
   * mesh in the server's order is fetched first when it was not yet.
   */
  async restore(meshId: string, kind: SelectionKind, ids: readonly number[]): Promise<void> {
    const source = this.source;
    if (!source || source.meshId !== meshId) return;
    if (this.target?.meshId !== meshId) {
      const ply = await source.load(meshId);
      if (this.source !== source) return;
      if (this.target?.meshId !== meshId) this.setMesh(meshId, ply);
    }
    this.setKind(kind);
    this.set([...ids]);
  }

  invert(): void {
    const t = this.target;
    if (t) this.set(invert(this.ids, this.kindNow === 'faces' ? t.ply.faces : t.ply.vertices));
  }

  grow(): void {
    const t = this.target;
    if (t) this.set(growShrink(this.kindNow, this.ids, t.ply.indices, t.ply.vertices, true));
  }

  shrink(): void {
    const t = this.target;
    if (t) this.set(growShrink(this.kindNow, this.ids, t.ply.indices, t.ply.vertices, false));
  }

  /** Selects what a region of the view (CSS pixels from the canvas's top left) holds. */
  selectRegion(region: Region, how: Combine = 'replace'): void {
    const t = this.target;
    if (!t) return;
    const { width, height, viewProjection } = this.modelView();
    const visible = this.through ? null : this.visibleFaces(regionBounds(region));
    if (this.kindNow === 'faces') {
      const projected = projectPoints(t.centroids, viewProjection, width, height);
      this.set(
        combine(
          this.ids,
          pointsInRegion(projected, region, (f) => !visible || visible.has(f)),
          how,
        ),
      );
    } else {
      const projected = projectPoints(t.ply.positions, viewProjection, width, height);
      const seen = (v: number) => {
        if (!visible) return true;
        for (let k = t.around.offsets[v]!; k < t.around.offsets[v + 1]!; ++k) if (visible.has(t.around.items[k]!)) return true;
        return false;
      };
      this.set(combine(this.ids, pointsInRegion(projected, region, seen), how));
    }
  }

  /** Picks the face (or its vertex nearest the point) drawn at (x, y) in CSS pixels. */
  pick(x: number, y: number, how: Combine = 'replace'): void {
    const t = this.target;
    if (!t) return;
    const faces = this.visibleFaces([x, y, x, y]);
    const f = faces.values().next().value;
    if (f === undefined) {
      if (how === 'replace') this.set([]);
      return;
    }
    if (this.kindNow === 'faces') {
      this.set(combine(this.ids, [f], how));
      return;
    }
    const { width, height, viewProjection } = this.modelView();
    const corners = new Float32Array(9);
    for (let c = 0; c < 3; ++c) corners.set(t.ply.positions.subarray(3 * t.ply.indices[3 * f + c]!, 3 * t.ply.indices[3 * f + c]! + 3), 3 * c);
    const p = projectPoints(corners, viewProjection, width, height);
    let best = 0;
    const d = (c: number) => (p[2 * c]! - x) ** 2 + (p[2 * c + 1]! - y) ** 2;
    for (let c = 1; c < 3; ++c) if (d(c) < d(best)) best = c;
    this.set(combine(this.ids, [t.ply.indices[3 * f + best]!], how));
  }

  /** The camera's view: the canvas size in CSS pixels and projection × view, column-major. */
  view(): { width: number; height: number; viewProjection: number[] } {
    const camera = this.viewer.camera;
    camera.updateMatrixWorld();
    const m = new THREE.Matrix4().multiplyMatrices(camera.projectionMatrix, camera.matrixWorldInverse);
    const canvas = this.viewer.renderer.domElement;
    return { width: canvas.clientWidth, height: canvas.clientHeight, viewProjection: m.toArray() };
  }

  /** Where the mesh selected on stands: the shown object's world matrix (identity when nothing is shown). */
  private model(): THREE.Matrix4 {
    const object = this.viewer.object;
    if (!object) return new THREE.Matrix4();
    object.updateWorldMatrix(true, false);
    return object.matrixWorld.clone();
  }

  /** view(), with the stored positions carried where the shown object stands. */
  private modelView(): { width: number; height: number; viewProjection: number[] } {
    const v = this.view();
    const m = new THREE.Matrix4().fromArray(v.viewProjection).multiply(this.model());
    return { ...v, viewProjection: m.toArray() };
  }

  private set(ids: number[]): void {
    this.ids = ids;
    this.drawHighlight();
    this.viewer.redraw(() => this.onChange(this.state()));
  }

  private drawHighlight(): void {
    const t = this.target;
    if (!t || this.ids.length === 0) {
      this.viewer.setOverlay('selection', null);
      return;
    }
    const object = highlight(t.ply, this.kindNow, this.ids);
    object.renderOrder = 1;
    // Follows the shown object as it is turned or moved, without a redraw of the highlight.
    object.matrixAutoUpdate = false;
    object.matrix.copy(this.model());
    object.frustumCulled = false;
    object.onBeforeRender = () => {
      const shown = this.viewer.object;
      if (!shown) return;
      object.matrix.copy(shown.matrixWorld);
      object.matrixWorld.copy(shown.matrixWorld);
    };
    this.viewer.setOverlay('selection', object);
  }

  /** The ids of the faces drawn in a rectangle of the view (CSS pixels), from the id buffer. */
  private visibleFaces(rect: [number, number, number, number]): Set<number> {
    const t = this.target!;
    const renderer = this.viewer.renderer;
    const canvas = renderer.domElement;
    const size = renderer.getDrawingBufferSize(new THREE.Vector2());
    const scale = size.x / Math.max(1, canvas.clientWidth);
    if (!this.renderTarget) this.renderTarget = new THREE.WebGLRenderTarget(size.x, size.y);
    if (this.renderTarget.width !== size.x || this.renderTarget.height !== size.y) this.renderTarget.setSize(size.x, size.y);
    if (!t.idMesh) {
      t.idMesh = idMesh(t.ply);
      t.idMesh.matrixAutoUpdate = false;
      this.idScene.add(t.idMesh);
    }
    t.idMesh.matrix.copy(this.model());
    const clear = renderer.getClearColor(new THREE.Color());
    const alpha = renderer.getClearAlpha();
    renderer.setRenderTarget(this.renderTarget);
    renderer.setClearColor(0x000000, 1);
    renderer.clear();
    renderer.render(this.idScene, this.viewer.camera);
    const x0 = Math.max(0, Math.floor(rect[0] * scale));
    const x1 = Math.min(size.x - 1, Math.floor(rect[2] * scale));
    // GL's rows go up from the bottom.
    const y0 = Math.max(0, Math.floor(size.y - 1 - rect[3] * scale));
    const y1 = Math.min(size.y - 1, Math.floor(size.y - 1 - rect[1] * scale));
    const out = new Set<number>();
    if (x1 >= x0 && y1 >= y0) {
      const w = x1 - x0 + 1,
        h = y1 - y0 + 1;
      const pixels = new Uint8Array(4 * w * h);
      renderer.readRenderTargetPixels(this.renderTarget, x0, y0, w, h, pixels);
      for (let i = 0; i < w * h; ++i) {
        const id = pixels[4 * i]! | (pixels[4 * i + 1]! << 8) | (pixels[4 * i + 2]! << 16);
        if (id) out.add(id - 1);
      }
    }
    renderer.setRenderTarget(null);
    renderer.setClearColor(clear, alpha);
    return out;
  }

  private down(e: PointerEvent): void {
    if (!this.active || e.button !== 0 || !this.target) return;
    const how: Combine = e.ctrlKey || e.metaKey ? 'subtract' : e.shiftKey ? 'add' : 'replace';
    const [x, y] = this.local(e);
    this.drag = { points: [x, y], how, id: e.pointerId };
    this.viewer.renderer.domElement.setPointerCapture(e.pointerId);
    e.preventDefault();
  }

  private move(e: PointerEvent): void {
    const d = this.drag;
    if (!d || e.pointerId !== d.id) return;
    const [x, y] = this.local(e);
    if (this.shape === 'lasso') d.points.push(x, y);
    else d.points = [d.points[0]!, d.points[1]!, x, y];
    this.drawRegion();
  }

  private up(e: PointerEvent): void {
    const d = this.drag;
    if (!d || e.pointerId !== d.id) return;
    const [x, y] = this.local(e);
    this.endDrag();
    const [sx, sy] = d.points as [number, number];
    if (Math.hypot(x - sx, y - sy) < 4 && d.points.length <= 4) {
      this.pick(x, y, d.how);
    } else if (this.shape === 'lasso') {
      d.points.push(x, y);
      if (d.points.length >= 6) this.selectRegion({ polygon: d.points }, d.how);
    } else {
      this.selectRegion({ rect: [Math.min(sx, x), Math.min(sy, y), Math.max(sx, x), Math.max(sy, y)] }, d.how);
    }
  }

  private endDrag(): void {
    this.drag = null;
    this.svg.classList.remove('dragging');
  }

  private drawRegion(): void {
    const d = this.drag!;
    let p = d.points;
    if (this.shape === 'box' && p.length === 4) p = [p[0]!, p[1]!, p[2]!, p[1]!, p[2]!, p[3]!, p[0]!, p[3]!];
    this.path.setAttribute('points', p.join(' '));
    this.svg.classList.add('dragging');
  }

  private local(e: PointerEvent): [number, number] {
    const r = this.viewer.renderer.domElement.getBoundingClientRect();
    return [e.clientX - r.left, e.clientY - r.top];
  }
}
