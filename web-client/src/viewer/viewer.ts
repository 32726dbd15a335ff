// The one three.js scene: renderer, camera, lights, orbit controls, resize
// handling and fit-to-view. It holds at most one shown object at a time and
// disposes of it when another replaces it (three-gltf-viewer's clear()).
// Frames are rendered on demand (after a change), not continuously.
//
// Panes (a comparison of fields side by side): the viewer can draw several
// objects, each in its own viewport of the one canvas, all through the one
// camera. One WebGLRenderer with setViewport/setScissor per pane rather than
// a canvas per pane: a single WebGL context (browsers cap them, and software
// GL pays for each), the lights and overlays are shared, and the views are
// synchronized by construction, since the orbit controls move the one camera
// that every pane is drawn with; nothing copies camera state between views.
// The scene's objects side by side use the same panes with objects already
// shown (setPanes(..., owned = false)).
//
// The near and far planes follow the camera: before every frame they are
// set from the camera's distance to the box of what that frame draws (every
// pane's object, the overlays): viewer/framing.ts.
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';
import { followBox, frameBox } from './framing.ts';

export const BACKGROUND = '#1b1d22';

/** Columns and rows of the grid of `n` panes: side by side up to 3, then 2 by 2 (and so on); one cell for none. */
export function paneGrid(n: number): { cols: number; rows: number } {
  const cols = n <= 3 ? Math.max(1, n) : Math.ceil(Math.sqrt(n));
  return { cols, rows: Math.max(1, Math.ceil(n / cols)) };
}

export interface ViewerOptions {
  /** Called after every rendered frame. */
  onFrame?: () => void;
}

export class Viewer {
  readonly renderer: THREE.WebGLRenderer;
  readonly scene = new THREE.Scene();
  readonly camera = new THREE.PerspectiveCamera(40, 1, 0.01, 100);
  readonly controls: OrbitControls;
  private readonly container: HTMLElement;
  private readonly options: ViewerOptions;
  private readonly resizeObserver: ResizeObserver;
  private shown: THREE.Object3D | null = null;
  /** Objects shown beside the main one (mesh artifacts of jobs, the scene's other meshes); cleared by show(). */
  private readonly extras = new THREE.Group();
  /** Objects drawn each in its own pane, in place of the shown one and the extras; empty: one view. */
  private panes: THREE.Object3D[] = [];
  /** Whether the panes are the viewer's own (added for them, disposed with them) or objects already shown (the scene's). */
  private panesOwned = true;
  private frameRequested = false;
  private afterFrame: Array<() => void> = [];
  /** Called when the shown object changes (display modes and overlays follow it). */
  private readonly shownListeners: Array<(object: THREE.Object3D | null) => void> = [];
  /** Called when the panes change (display modes follow the comparison's objects). */
  private readonly panesListeners: Array<(owned: readonly THREE.Object3D[]) => void> = [];

  constructor(container: HTMLElement, options: ViewerOptions = {}) {
    this.container = container;
    this.options = options;

    this.renderer = new THREE.WebGLRenderer({ antialias: true });
    this.renderer.setPixelRatio(Math.min(window.devicePixelRatio || 1, 2));
    this.renderer.domElement.classList.add('viewer-canvas');
    container.appendChild(this.renderer.domElement);

    this.scene.background = new THREE.Color(BACKGROUND);

    // Soft sky/ground fill, plus a key and a rim light that follow the camera
    // so the surface reads well from every side.
    this.scene.add(new THREE.HemisphereLight(0xf2f4ff, 0x2a2622, 0.8));
    const key = new THREE.DirectionalLight(0xffffff, 2.4);
    key.position.set(-1, 1.5, 1.2);
    const fill = new THREE.DirectionalLight(0xffffff, 0.5);
    fill.position.set(1.5, -0.2, 0.8);
    const rim = new THREE.DirectionalLight(0xcfd8ff, 0.6);
    rim.position.set(0.5, 0.8, -1.5);
    this.camera.add(key, fill, rim);
    this.scene.add(this.camera);
    this.scene.add(this.extras);

    this.camera.position.set(0, 0, 3);
    this.controls = new OrbitControls(this.camera, this.renderer.domElement);
    this.controls.enableDamping = true;
    this.controls.dampingFactor = 0.12;
    this.controls.addEventListener('change', () => this.requestRender());

    this.resizeObserver = new ResizeObserver(() => this.resize());
    this.resizeObserver.observe(container);
    this.resize();
  }

  /**
   * Calls `listener` whenever the shown object changes (show, replace,
   * clear), before the first frame that draws it.
   */
  onShownChange(listener: (object: THREE.Object3D | null) => void): void {
    this.shownListeners.push(listener);
  }

  /**
   * Calls `listener` whenever the panes change, with the objects the viewer
   * owns in them (made for a comparison; none for the scene's side by side,
   * whose objects are the shown one and the extras), before the first frame
   * that draws them.
   */
  onPanesChange(listener: (owned: readonly THREE.Object3D[]) => void): void {
    this.panesListeners.push(listener);
  }

  /** The objects the viewer owns in its panes (see onPanesChange). */
  get ownPanes(): readonly THREE.Object3D[] {
    return this.panesOwned ? this.panes : [];
  }

  private shownChanged(): void {
    for (const listener of this.shownListeners) listener(this.shown);
  }

  /** The object now shown, or null. */
  get object(): THREE.Object3D | null {
    return this.shown;
  }

  /**
   * Shows `object` in place of the previous one (which is disposed), frames
   * the camera on its bounding sphere, and calls `onShown` after the first
   * frame with it has been rendered.
   */
  show(object: THREE.Object3D, onShown?: () => void): void {
    this.clear();
    this.clearExtras();
    this.shown = object;
    this.scene.add(object);
    this.shownChanged();
    this.fitToView();
    if (onShown) this.afterFrame.push(onShown);
    this.requestRender();
  }

  /**
   * Shows `object` in place of the previous one (disposed) without moving the
   * camera: the same surface drawn another way (a scalar field on it).
   */
  replace(object: THREE.Object3D, onShown?: () => void): void {
    if (!this.shown) {
      this.show(object, onShown);
      return;
    }
    this.clear();
    this.shown = object;
    this.scene.add(object);
    this.shownChanged();
    if (onShown) this.afterFrame.push(onShown);
    this.requestRender();
  }

  /** Adds an object beside the shown one (kept until the next show()); the camera stays. */
  addExtra(object: THREE.Object3D, onShown?: () => void): void {
    this.extras.add(object);
    if (onShown) this.afterFrame.push(onShown);
    this.requestRender();
  }

  /** Shows `object` as the overlay of that name (a voxel slice plane), replacing and
   * disposing of the previous one; null removes it. */
  setOverlay(name: string, object: THREE.Object3D | null): void {
    const old = this.scene.getObjectByName(`overlay:${name}`);
    if (old) {
      this.scene.remove(old);
      disposeObject(old);
    }
    if (object) {
      object.name = `overlay:${name}`;
      this.scene.add(object);
    }
    this.requestRender();
  }

  /** Cuts everything shown by a plane (the part where plane.distanceToPoint < 0 is
   * hidden): the section view at a voxel slice; null shows all again. */
  setClipPlane(plane: THREE.Plane | null): void {
    this.renderer.clippingPlanes = plane ? [plane] : [];
    this.requestRender();
  }

  /** Removes and disposes of one object added with addExtra(). */
  removeExtra(object: THREE.Object3D): void {
    if (object.parent !== this.extras) return;
    this.extras.remove(object);
    disposeObject(object);
    this.requestRender();
  }

  /**
   * Draws `objects` side by side, each in its own pane through the shared
   * camera, in place of the shown object and the extras (kept, hidden, until
   * setPanes([]) ends the comparison); the previous panes are disposed.
   * With `owned` false the objects are some already shown (the shown one
   * and extras: the scene side by side), drawn one per pane and left in
   * place, not disposed, when the panes end; one hidden stays hidden.
   */
  setPanes(objects: THREE.Object3D[], onShown?: () => void, owned = true): void {
    if (this.panesOwned) {
      for (const o of this.panes) {
        this.scene.remove(o);
        disposeObject(o);
      }
    }
    const cols = paneGrid(this.panes.length).cols;
    this.panes = objects;
    this.panesOwned = owned;
    if (owned) for (const o of objects) this.scene.add(o);
    for (const listener of this.panesListeners) listener(this.ownPanes);
    this.resize();
    // Panes of another width: frame the surface again so that it fits them.
    if (paneGrid(objects.length).cols !== cols) this.fitToView();
    if (onShown) this.afterFrame.push(onShown);
    this.requestRender();
  }

  /** Removes and disposes of the objects added with addExtra(). */
  clearExtras(): void {
    for (const child of [...this.extras.children]) {
      this.extras.remove(child);
      disposeObject(child);
    }
    this.requestRender();
  }

  /** Draws a frame (after a change to the shown object), then calls `onDrawn`. */
  redraw(onDrawn?: () => void): void {
    if (onDrawn) this.afterFrame.push(onDrawn);
    this.requestRender();
  }

  /** Removes and disposes of the shown object. */
  clear(): void {
    if (!this.shown) return;
    this.scene.remove(this.shown);
    disposeObject(this.shown);
    this.shown = null;
    this.shownChanged();
    this.requestRender();
  }

  /** Removes the shown object, everything beside it and the panes. */
  clearAll(): void {
    this.setPanes([]);
    this.clear();
    this.clearExtras();
  }

  /** Frames the camera on the shown object's bounding sphere, looking from the front-right-above. */
  fitToView(): void {
    const target = this.shown ?? this.panes[0];
    if (target) this.fitBox(new THREE.Box3().setFromObject(target));
  }

  /** Frames every visible object: the shown one, the extras beside it (the scene's objects) and the panes. */
  fitAll(): void {
    this.fitBox(this.visibleBox());
  }

  /** The world box of the visible objects (the shown one, the extras, the panes), empty when none. */
  visibleBox(): THREE.Box3 {
    const box = new THREE.Box3();
    const objects = [this.shown, ...this.extras.children, ...this.panes];
    for (const o of new Set(objects)) if (o && o.visible) box.union(new THREE.Box3().setFromObject(o));
    return box;
  }

  /** Frames `box`'s bounding sphere, looking from the front-right-above. */
  private fitBox(box: THREE.Box3): void {
    frameBox(this.camera, this.controls, box);
    this.requestRender();
  }

  /** The world box of what a frame draws: the visible objects and the overlays over them. */
  private drawnBox(): THREE.Box3 {
    const box = this.visibleBox();
    for (const o of this.scene.children) if (o.visible && o.name.startsWith('overlay:')) box.union(new THREE.Box3().setFromObject(o));
    return box;
  }

  /** Renders one frame at the next animation frame (several requests make one frame). */
  requestRender(): void {
    if (this.frameRequested) return;
    this.frameRequested = true;
    requestAnimationFrame(() => this.frame());
  }

  dispose(): void {
    this.clearAll();
    this.resizeObserver.disconnect();
    this.controls.dispose();
    this.renderer.dispose();
    this.renderer.domElement.remove();
  }

  private resize(): void {
    const width = Math.max(1, this.container.clientWidth);
    const height = Math.max(1, this.container.clientHeight);
    this.renderer.setSize(width, height, false);
    const { cols, rows } = paneGrid(this.panes.length);
    this.camera.aspect = width / cols / (height / rows);
    this.camera.updateProjectionMatrix();
    this.requestRender();
  }

  private frame(): void {
    this.frameRequested = false;
    // With damping, update() keeps moving the camera for a few frames after
    // the pointer stops; it fires 'change', which asks for the next frame.
    // Off while another navigation mode or the selection tool has the mouse
    // (its update() would turn the camera back to the orbit target).
    if (this.controls.enabled && !this.controls.update()) this.settleControls();
    followBox(this.camera, this.controls.target, this.drawnBox());
    if (this.panes.length) this.renderPanes();
    else this.renderer.render(this.scene, this.camera);
    this.options.onFrame?.();
    const callbacks = this.afterFrame;
    this.afterFrame = [];
    for (const cb of callbacks) cb();
  }

  /**
   * Ends the damping's glide at once. update() stops firing 'change' once a
   * step moves the camera less than 1e-3, but what is left of the motion
   * would still move it a little at every later frame (a screenshot, a
   * recoloured field), so that a view link read now would not draw the same
   * picture again. One undamped update applies the rest and zeroes it.
   */
  private settleControls(): void {
    this.controls.enableDamping = false;
    this.controls.update();
    this.controls.enableDamping = true;
  }

  /** Pane `i`'s cell of the canvas, in GL's pixels (origin at the bottom left; row 0 is the top); null: no such pane. */
  paneRect(i: number): { x: number; y: number; width: number; height: number } | null {
    if (i < 0 || i >= this.panes.length) return null;
    const { x: width, y: height } = this.renderer.getSize(new THREE.Vector2());
    const { cols, rows } = paneGrid(this.panes.length);
    const col = i % cols;
    const row = Math.floor(i / cols);
    const x0 = Math.round((col * width) / cols);
    const x1 = Math.round(((col + 1) * width) / cols);
    const y0 = Math.round(height - ((row + 1) * height) / rows);
    const y1 = Math.round(height - (row * height) / rows);
    return { x: x0, y: y0, width: x1 - x0, height: y1 - y0 };
  }

  /** The pane that draws `object` (or one of its ancestors), or -1. */
  paneOf(object: THREE.Object3D): number {
    return this.panes.findIndex((p) => p === object || p.getObjectById(object.id) !== undefined);
  }

  /**
   * Draws each pane in its cell of the grid, everything else hidden (the
   * clear, too, is scissored to the cell). A pane that was hidden (a scene
   * object switched off) draws an empty cell.
   */
  private renderPanes(): void {
    const { x: width, y: height } = this.renderer.getSize(new THREE.Vector2());
    const all = [...new Set([this.shown, this.extras, ...this.extras.children, ...this.panes])].filter((o) => o !== null);
    const wasVisible = new Map(all.map((o) => [o, o.visible]));
    for (const o of all) o.visible = false;
    // Panes among the extras (the scene's) need their group drawn.
    if (!this.panesOwned) this.extras.visible = true;
    this.renderer.setScissorTest(true);
    this.panes.forEach((pane, i) => {
      const r = this.paneRect(i)!;
      pane.visible = wasVisible.get(pane)!;
      this.renderer.setViewport(r.x, r.y, r.width, r.height);
      this.renderer.setScissor(r.x, r.y, r.width, r.height);
      this.renderer.render(this.scene, this.camera);
      pane.visible = false;
    });
    this.renderer.setScissorTest(false);
    this.renderer.setViewport(0, 0, width, height);
    for (const [o, v] of wasVisible) o.visible = v;
  }
}

/** Frees the GPU resources of an object and its children. */
export function disposeObject(root: THREE.Object3D): void {
  root.traverse((node) => {
    const mesh = node as THREE.Mesh;
    if (mesh.geometry) mesh.geometry.dispose();
    const material = mesh.material as THREE.Material | THREE.Material[] | undefined;
    if (Array.isArray(material)) material.forEach((m) => m.dispose());
    else material?.dispose();
  });
}
