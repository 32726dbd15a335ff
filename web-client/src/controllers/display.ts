// The display: the shown surface's mode and material and the overlays over it,
// as the state holds them (AppState.display), applied to whatever the viewer
// shows (viewer.onShownChange), so that a mesh shown later keeps the mode
// chosen. With several meshes in the scene, the mode and material apply to
// every object of it, each in its own colour where the scene gives one
// (panels/scene.ts); the overlays are of the shown (first) one, or of the
// scene object picked. A comparison's panes (fields or skeletons side by
// side) draw their surfaces in the mode too (viewer.onPanesChange). The up
// axis of the shown mesh is chosen here too (viewer/up_axis.ts): the one the
// user chose for it, else the one its file's format implies. The Display
// panel (panels/display.ts) shows and edits the settings.
import * as THREE from 'three';
import { RoomEnvironment } from 'three/addons/environments/RoomEnvironment.js';
import { saveBlob } from '../api/auth.ts';
import { DisplayPanel } from '../panels/display.ts';
import type { AppStore } from '../state/app_state.ts';
import { creaseOf, creaseRefusal } from '../viewer/crease.ts';
import { applyCrease, applyDisplay, isDefaultDisplay, isSurface, sanitizeDisplay, type DisplaySettings } from '../viewer/display_modes.ts';
import { percentileRange } from '../viewer/histogram.ts';
import { sanitizeOverlays, updateOverlays, type OverlayInfo, type OverlaySettings } from '../viewer/overlays.ts';
import { defaultUpAxis, setObjectUp, storeUpAxis, storedUpAxis, type UpAxis } from '../viewer/up_axis.ts';
import { isPointCloud, pointsReport, setPointsLook } from '../viewer/points_renderer.ts';
import type { Viewer } from '../viewer/viewer.ts';

/** What the display reports after each change has been drawn (window.__cgview.display). */
export interface DisplayReport extends DisplaySettings, OverlayInfo {
  overlays: OverlaySettings;
  /** The shown object's name ("surface", "scalar:NAME"), or null. */
  object: string | null;
  /** The shown mesh's up axis. */
  up: UpAxis;
  /** The crease angle the shown surface is drawn with; null: as built (180°, its file's normals, not a surface). */
  crease: number | null;
  /** The shown point cloud as drawn (its points, their size in pixels, its colours and normals used); null: no cloud shown. */
  cloud: ReturnType<typeof pointsReport> | null;
}

export interface DisplayCallbacks {
  /** A new range for the field drawn (null: its full range). */
  setFieldRange: (range: [number, number] | null) => void;
  /** Called after a frame shows the settings. */
  drawn: (report: DisplayReport) => void;
  /** The scene's other objects, drawn in the same mode (none by default). */
  others?: () => THREE.Object3D[];
  /** An object's own colour in the scene, in place of the material's; null: the material's. */
  colorOf?: (object: THREE.Object3D) => string | null;
  /** The mesh an object of the scene draws (its up axis is that mesh's), or null. */
  meshOf?: (object: THREE.Object3D) => string | null;
  /** A mesh's file format ("stl", "glb"...), which gives its up axis until one is chosen; null: not known. */
  formatOf?: (meshId: string) => string | null;
}

export class DisplayController {
  private info: OverlayInfo = { size: null, boundaryEdges: null, nonManifoldEdges: null };
  private object: THREE.Object3D | null = null;
  /** The surfaces of a comparison's panes (fields, skeletons over the mesh), drawn in the mode as the shown one is. */
  private paneSurfaces: THREE.Mesh[] = [];
  /** The objects of a comparison's panes, all of the shown mesh: they are drawn with its up axis. */
  private paneObjects: readonly THREE.Object3D[] = [];
  /** The scene object whose overlays are drawn, when not the shown one. */
  private overlayObject: THREE.Object3D | null = null;
  private environment: THREE.Texture | null = null;
  /** The values of the field drawn, for its 1–99% range. */
  private fieldValues: Float32Array | null = null;
  /** While a view link's settings are taken: they are applied all at once after. */
  private restoring = false;
  /** Whether points are drawn over the shown object (a job's points): the point size applies to them. */
  private pointsOver = false;
  private readonly panel: DisplayPanel;

  constructor(
    root: HTMLElement,
    private readonly store: AppStore,
    private readonly viewer: Viewer,
    private readonly callbacks: DisplayCallbacks,
  ) {
    this.panel = new DisplayPanel(root, store, {
      setDisplay: (settings) => store.update((s) => ({ display: { ...s.display, settings } })),
      setOverlays: (overlays) => store.update((s) => ({ display: { ...s.display, overlays } })),
      setUpAxis: (axis) => this.setUpAxis(axis),
      setFieldRange: (range) => callbacks.setFieldRange(range),
      clipField: () => {
        if (this.fieldValues) callbacks.setFieldRange(percentileRange(this.fieldValues, 1, 99));
      },
    });
    store.subscribe(
      (s) => s.display.settings,
      () => {
        if (this.restoring) return;
        for (const o of this.targets()) this.applyTo(o);
        this.report();
      },
    );
    store.subscribe(
      (s) => s.display.overlays,
      () => {
        if (!this.restoring) this.refreshOverlays();
      },
    );
    viewer.onShownChange((object) => this.attach(object));
    viewer.onPanesChange((panes) => this.attachPanes(panes));
  }

  private get settings(): DisplaySettings {
    return this.store.get().display.settings;
  }

  private get overlays(): OverlaySettings {
    return this.store.get().display.overlays;
  }

  /** The settings, for the view link. */
  state(): { display: DisplaySettings; overlays: OverlaySettings } {
    return { display: { ...this.settings }, overlays: { ...this.overlays } };
  }

  /** Takes settings from a view link (untrusted: checked, invalid values fall back to the defaults). */
  restore(display: Record<string, unknown> | undefined, overlays: Record<string, unknown> | undefined): void {
    this.restoring = true;
    try {
      this.store.update({ display: { settings: sanitizeDisplay(display), overlays: sanitizeOverlays(overlays) } });
    } finally {
      this.restoring = false;
    }
    for (const o of this.targets()) this.applyTo(o);
    this.refreshOverlays();
  }

  /** The shown mesh's up axis. */
  upAxis(): UpAxis {
    const mesh = this.object && this.meshOf(this.object);
    return mesh ? this.upOf(mesh) : 'y';
  }

  /** A mesh's up axis: the one chosen for it, else its format's. */
  private upOf(mesh: string): UpAxis {
    return storedUpAxis(mesh, defaultUpAxis(this.callbacks.formatOf?.(mesh) ?? null));
  }

  /**
   * Makes `axis` the shown mesh's up axis: kept for the mesh, put on its
   * objects (the shown one, its panes, its copies in the scene), and the
   * view framed again, since the objects turned.
   */
  setUpAxis(axis: UpAxis): void {
    const mesh = this.object && this.meshOf(this.object);
    if (!mesh) {
      this.panel.showUp('y');
      return;
    }
    storeUpAxis(mesh, axis, defaultUpAxis(this.callbacks.formatOf?.(mesh) ?? null));
    this.panel.showUp(axis);
    let turned = false;
    for (const o of [...(this.object ? [this.object] : []), ...(this.callbacks.others?.() ?? []), ...this.paneObjects]) {
      if (this.meshOfOrShown(o) === mesh && setObjectUp(o, axis)) turned = true;
    }
    if (!turned) return;
    this.viewer.fitAll();
    this.refreshOverlays();
  }

  /** The mesh an object draws; the panes' objects are the shown mesh's. */
  private meshOfOrShown(object: THREE.Object3D): string | null {
    if (this.paneObjects.includes(object)) return this.object && this.meshOf(this.object);
    return this.meshOf(object);
  }

  private meshOf(object: THREE.Object3D): string | null {
    return this.callbacks.meshOf?.(object) ?? null;
  }

  /** The field drawn now (its range and full range, and its values for percentiles), or null. */
  setField(field: { range: [number, number]; full: [number, number]; values: Float32Array } | null): void {
    this.fieldValues = field?.values ?? null;
    this.panel.showField(field && field.range);
  }

  /** Shows the view link's URL in the panel. */
  showLink(url: string): void {
    this.panel.showLink(url);
  }

  /** Downloads the canvas as a PNG, drawn afresh (the drawing buffer is read in the frame's own task). */
  screenshot(fileName: string, done?: (blob: Blob | null) => void): void {
    this.viewer.redraw(() => {
      this.viewer.renderer.domElement.toBlob((blob) => {
        if (blob) saveBlob(blob, fileName);
        done?.(blob);
      }, 'image/png');
    });
  }

  /** Draws `object` (one of the scene's) in the mode and material, in its own colour. */
  applyTo(object: THREE.Object3D | null): void {
    const mesh = object && this.meshOf(object);
    if (mesh) setObjectUp(object, this.upOf(mesh));
    const color = object ? (this.callbacks.colorOf?.(object) ?? null) : null;
    if (isPointCloud(object)) return setPointsLook(object, color ? { ...this.settings, color } : this.settings);
    if (!isSurface(object)) return;
    applyDisplay(object, color ? { ...this.settings, color } : this.settings, () => this.env());
  }

  private targets(): THREE.Object3D[] {
    return [...(this.object ? [this.object] : []), ...(this.callbacks.others?.() ?? []), ...this.paneSurfaces];
  }

  /** Draws the overlays over `object` (a scene object chosen in the Scene panel); null: over the shown one. */
  setOverlayObject(object: THREE.Object3D | null): void {
    this.overlayObject = object;
    this.refreshOverlays();
  }

  /** Builds the overlays again (their object moved). */
  refreshOverlays(): void {
    this.info = updateOverlays(this.viewer, this.overlayObject ?? this.object, this.overlays);
    this.report();
  }

  /** A new shown object: the mode and the overlays follow it (a default display leaves it as built). */
  private attach(object: THREE.Object3D | null): void {
    this.object = object;
    const mesh = object && this.meshOf(object);
    // Before the viewer frames it: the camera frames the object as drawn, turned.
    if (mesh) setObjectUp(object, this.upOf(mesh));
    this.panel.showUp(mesh ? this.upOf(mesh) : 'y');
    if (object && (!isDefaultDisplay(this.settings) || this.callbacks.colorOf?.(object) || isPointCloud(object))) this.applyTo(object);
    else if (isSurface(object)) applyCrease(object, this.settings);
    this.showObject();
    this.refreshOverlays();
  }

  /** Whether points are drawn over the shown object (a job's points): the Display panel offers their size then. */
  setPointsOver(drawn: boolean): void {
    if (drawn === this.pointsOver) return;
    this.pointsOver = drawn;
    this.showObject();
  }

  /** The controls that apply to what is shown. */
  private showObject(): void {
    const object = this.object;
    const cloud = isPointCloud(object);
    // The slider stays for the other objects of the scene, but says when it does not apply to the shown one.
    this.panel.showObject({
      creaseRefusal: isSurface(object) ? creaseRefusal(object) : null,
      vertexColors: Boolean((isSurface(object) || cloud) && object.geometry.getAttribute('color') && !object.name.startsWith('scalar:')),
      points: cloud || this.pointsOver,
    });
  }

  /** New panes of a comparison: their surfaces (a pane's object, or the surfaces in its group) are drawn in the mode too. */
  private attachPanes(panes: readonly THREE.Object3D[]): void {
    this.paneObjects = [...panes];
    const axis = this.upAxis();
    for (const p of panes) setObjectUp(p, axis);
    this.paneSurfaces = panes.flatMap((p) => (isSurface(p) ? [p] : p.children.filter(isSurface)));
    if (!isDefaultDisplay(this.settings)) for (const o of this.paneSurfaces) this.applyTo(o);
    else for (const o of this.paneSurfaces) applyCrease(o, this.settings);
  }

  /** Reflections for metals: a PMREM of three's room environment, made once, when first needed. */
  private env(): THREE.Texture {
    if (!this.environment) {
      const pmrem = new THREE.PMREMGenerator(this.viewer.renderer);
      const room = new RoomEnvironment();
      this.environment = pmrem.fromScene(room, 0.04).texture;
      room.dispose();
      pmrem.dispose();
    }
    return this.environment;
  }

  /** Updates the panel's readout, and tells the app once a frame shows the settings. */
  private report(): void {
    this.panel.showInfo(this.info);
    const object = this.object;
    const report: DisplayReport = {
      ...this.settings,
      ...this.info,
      overlays: { ...this.overlays },
      object: object?.name ?? null,
      up: this.upAxis(),
      crease: isSurface(object) ? creaseOf(object) : null,
      cloud: isPointCloud(object) ? pointsReport(object) : null,
    };
    this.viewer.redraw(() => {
      if (this.object === object) this.callbacks.drawn(report);
    });
  }
}
