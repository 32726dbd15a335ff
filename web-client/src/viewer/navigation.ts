// How the camera moves: orbit (three's OrbitControls, the viewer's own, the
// default), trackball (TrackballControls: no fixed up, the view rolls
// freely) or fly (WASD and mouse-look, our own: FlyControls listens to every
// key of the window, form fields included); views along the axes and reset;
// a 3D mouse through WebHID (viewer/spacemouse.ts).
//
// Touch: OrbitControls and TrackballControls take touch input themselves
// (one finger rotates, two pinch to zoom and pan; the canvas has
// touch-action: none so that the page does not scroll instead). Fly mode
// looks around with one finger.
//
// All modes move the one camera; the orbit centre (OrbitControls' target) is
// kept as the centre of the other modes too, so that switching back and forth
// and the axis views stay about the same point.
import * as THREE from 'three';
import { TrackballControls } from 'three/addons/controls/TrackballControls.js';
import { cameraMotion, parseSpaceMouseReport, SPACEMOUSE_VENDORS } from './spacemouse.ts';
import type { Viewer } from './viewer.ts';

export type NavigationMode = 'orbit' | 'trackball' | 'fly';
/** A view along an axis: the direction the camera looks in. */
export type AxisView = '+x' | '-x' | '+y' | '-y' | '+z' | '-z';

const AXES: Record<AxisView, [number, number, number]> = {
  '+x': [1, 0, 0],
  '-x': [-1, 0, 0],
  '+y': [0, 1, 0],
  '-y': [0, -1, 0],
  '+z': [0, 0, 1],
  '-z': [0, 0, -1],
};

/** The fly keys: forward, back, left, right, down, up. */
const FLY_KEYS: Record<string, [number, number, number]> = {
  KeyW: [0, 0, 1],
  ArrowUp: [0, 0, 1],
  KeyS: [0, 0, -1],
  ArrowDown: [0, 0, -1],
  KeyA: [-1, 0, 0],
  ArrowLeft: [-1, 0, 0],
  KeyD: [1, 0, 0],
  ArrowRight: [1, 0, 0],
  KeyQ: [0, -1, 0],
  KeyE: [0, 1, 0],
};

export interface CameraState {
  mode: NavigationMode;
  position: [number, number, number];
  /** The unit direction the camera looks in. */
  direction: [number, number, number];
  up: [number, number, number];
  target: [number, number, number];
  spaceMouse: string | null;
}

export class Navigation {
  private modeNow: NavigationMode = 'orbit';
  private enabled = true;
  private readonly viewer: Viewer;
  private trackball: TrackballControls | null = null;
  private readonly keys = new Set<string>();
  private look: { id: number; x: number; y: number } | null = null;
  /** The fly speed (units per second): half the distance to the centre when fly mode began. */
  private flySpeed = 1;
  private ticking = false;
  private last = 0;
  private spaceMouse: { name: string; translation: number[]; rotation: number[] } | null = null;

  constructor(viewer: Viewer) {
    this.viewer = viewer;
    const canvas = viewer.renderer.domElement;
    canvas.addEventListener('pointerdown', (e) => {
      if (this.modeNow !== 'fly' || !this.enabled || (e.pointerType === 'mouse' && e.button !== 0)) return;
      this.look = { id: e.pointerId, x: e.clientX, y: e.clientY };
      canvas.setPointerCapture(e.pointerId);
    });
    canvas.addEventListener('pointermove', (e) => {
      const l = this.look;
      if (!l || l.id !== e.pointerId) return;
      this.turn(-(e.clientX - l.x) * 0.004, -(e.clientY - l.y) * 0.004);
      l.x = e.clientX;
      l.y = e.clientY;
    });
    const endLook = () => (this.look = null);
    canvas.addEventListener('pointerup', endLook);
    canvas.addEventListener('pointercancel', endLook);
    window.addEventListener('keydown', (e) => {
      if (this.modeNow !== 'fly' || !this.enabled || !(e.code in FLY_KEYS) || typing(e.target)) return;
      this.keys.add(e.code);
      e.preventDefault();
      this.startTicking();
    });
    window.addEventListener('keyup', (e) => this.keys.delete(e.code));
    window.addEventListener('blur', () => this.keys.clear());
  }

  get mode(): NavigationMode {
    return this.modeNow;
  }

  /** The orbit centre: OrbitControls' target, which every mode keeps. */
  get target(): THREE.Vector3 {
    return this.viewer.controls.target;
  }

  setMode(mode: NavigationMode): void {
    if (mode === this.modeNow) return;
    const camera = this.viewer.camera;
    if (this.trackball) {
      this.target.copy(this.trackball.target);
      this.trackball.dispose();
      this.trackball = null;
    }
    if (this.modeNow === 'fly') {
      // Orbit about the point ahead at the old distance.
      const distance = Math.max(this.flySpeed * 2, 1e-6);
      this.target.copy(camera.position).addScaledVector(camera.getWorldDirection(new THREE.Vector3()), distance);
      this.keys.clear();
    }
    this.modeNow = mode;
    if (mode !== 'trackball') {
      // Orbit and fly keep +Y up; the trackball may have rolled the camera.
      camera.up.set(0, 1, 0);
      camera.lookAt(this.target);
    }
    if (mode === 'trackball') {
      const t = new TrackballControls(camera, this.viewer.renderer.domElement);
      t.target.copy(this.target);
      t.rotateSpeed = 3;
      t.zoomSpeed = 1.2;
      t.panSpeed = 0.8;
      t.addEventListener('change', () => this.viewer.requestRender());
      t.enabled = this.enabled;
      this.trackball = t;
    }
    if (mode === 'fly') this.flySpeed = camera.position.distanceTo(this.target) / 2;
    this.viewer.controls.enabled = mode === 'orbit' && this.enabled;
    this.viewer.requestRender();
    this.startTicking();
  }

  /** Pauses every mode (while the selection tool has the mouse) or resumes. */
  setEnabled(on: boolean): void {
    this.enabled = on;
    this.viewer.controls.enabled = on && this.modeNow === 'orbit';
    if (this.trackball) this.trackball.enabled = on;
    if (!on) {
      this.look = null;
      this.keys.clear();
    }
  }

  /** Looks along an axis at the centre, from the same distance ('-z': the front view, from +z). */
  viewAlong(axis: AxisView): void {
    const camera = this.viewer.camera;
    const dir = new THREE.Vector3(...AXES[axis]);
    const distance = camera.position.distanceTo(this.target) || 1;
    camera.position.copy(this.target).addScaledVector(dir, -distance);
    // +Y stays up; looking straight up or down, -Z / +Z is up on screen.
    camera.up.set(0, 1, 0);
    if (axis === '-y') camera.up.set(0, 0, -1);
    if (axis === '+y') camera.up.set(0, 0, 1);
    camera.lookAt(this.target);
    if (this.modeNow !== 'trackball') camera.up.set(0, 1, 0);
    this.trackball?.target.copy(this.target);
    this.viewer.requestRender();
  }

  /** Frames the shown object from the default direction with +Y up. */
  reset(): void {
    this.viewer.camera.up.set(0, 1, 0);
    this.viewer.fitToView();
    this.trackball?.target.copy(this.target);
    if (this.modeNow === 'fly') this.flySpeed = this.viewer.camera.position.distanceTo(this.target) / 2;
  }

  state(): CameraState {
    const c = this.viewer.camera;
    c.updateMatrixWorld();
    const d = c.getWorldDirection(new THREE.Vector3());
    const up = new THREE.Vector3(0, 1, 0).applyQuaternion(c.quaternion);
    return {
      mode: this.modeNow,
      position: c.position.toArray() as [number, number, number],
      direction: d.toArray() as [number, number, number],
      up: up.toArray() as [number, number, number],
      target: (this.trackball?.target ?? this.target).toArray() as [number, number, number],
      spaceMouse: this.spaceMouse?.name ?? null,
    };
  }

  /** Whether this browser offers WebHID (Chrome, Edge, Opera, in a secure context). */
  static hasHid(): boolean {
    return typeof navigator !== 'undefined' && 'hid' in navigator && window.isSecureContext;
  }

  /** Asks the user for a 3D mouse (the browser's device chooser) and listens to it; resolves with its name. */
  async connectSpaceMouse(): Promise<string> {
    const hid = (navigator as unknown as { hid: HidApi }).hid;
    const devices = await hid.requestDevice({ filters: SPACEMOUSE_VENDORS.map((vendorId) => ({ vendorId })) });
    const device = devices[0];
    if (!device) throw new Error('No 3D mouse was chosen.');
    if (!device.opened) await device.open();
    const state = { name: device.productName || '3D mouse', translation: [0, 0, 0], rotation: [0, 0, 0] };
    this.spaceMouse = state;
    device.addEventListener('inputreport', (e: HidInputReportEvent) => {
      const r = parseSpaceMouseReport(e.reportId, e.data);
      if (!r) return;
      if (r.translation) state.translation = r.translation;
      if (r.rotation) state.rotation = r.rotation;
      this.startTicking();
    });
    return state.name;
  }

  /** Turns the camera in place (fly): yaw about +Y, pitch about its right, kept short of straight up or down. */
  private turn(yaw: number, pitch: number): void {
    const camera = this.viewer.camera;
    const euler = new THREE.Euler().setFromQuaternion(camera.quaternion, 'YXZ');
    euler.y += yaw;
    euler.x = THREE.MathUtils.clamp(euler.x + pitch, -Math.PI / 2 + 0.01, Math.PI / 2 - 0.01);
    euler.z = 0;
    camera.quaternion.setFromEuler(euler);
    this.viewer.requestRender();
  }

  private startTicking(): void {
    if (this.ticking) return;
    this.ticking = true;
    this.last = performance.now();
    requestAnimationFrame((t) => this.tick(t));
  }

  /** Runs while a mode needs updates every frame: the trackball, fly keys held, the 3D mouse moved. */
  private tick(now: number): void {
    const dt = Math.min(0.1, Math.max(0, (now - this.last) / 1000));
    this.last = now;
    const camera = this.viewer.camera;
    let more = false;
    if (this.trackball) {
      this.trackball.update();
      more = true;
    }
    if (this.modeNow === 'fly' && this.keys.size && this.enabled) {
      const move = new THREE.Vector3();
      for (const k of this.keys) move.add(new THREE.Vector3(...(FLY_KEYS[k] ?? [0, 0, 0])));
      const forward = camera.getWorldDirection(new THREE.Vector3());
      const right = new THREE.Vector3().crossVectors(forward, camera.up).normalize();
      const step = this.flySpeed * dt;
      camera.position
        .addScaledVector(right, move.x * step)
        .addScaledVector(camera.up, move.y * step)
        .addScaledVector(forward, move.z * step);
      this.viewer.requestRender();
      more = true;
    }
    const sm = this.spaceMouse;
    if (sm && this.enabled) {
      const m = cameraMotion(sm.translation, sm.rotation);
      if (m.right || m.up || m.forward || m.yaw || m.pitch) {
        this.spaceMouseStep(m, dt);
        more = true;
      }
    }
    if (more) requestAnimationFrame((t) => this.tick(t));
    else this.ticking = false;
  }

  /** One frame of 3D-mouse motion: pan and dolly in the view's frame, orbit about the centre. */
  private spaceMouseStep(m: ReturnType<typeof cameraMotion>, dt: number): void {
    const camera = this.viewer.camera;
    const target = this.trackball?.target ?? this.target;
    const distance = camera.position.distanceTo(target);
    const forward = camera.getWorldDirection(new THREE.Vector3());
    const up = new THREE.Vector3(0, 1, 0).applyQuaternion(camera.quaternion);
    const right = new THREE.Vector3().crossVectors(forward, up).normalize();
    const pan = new THREE.Vector3().addScaledVector(right, m.right * distance * dt).addScaledVector(up, m.up * distance * dt);
    camera.position.add(pan);
    target.add(pan);
    // Dolly towards the centre, never through it.
    const dolly = Math.min(m.forward * distance * dt, distance * 0.9);
    camera.position.addScaledVector(forward, dolly);
    if (this.modeNow === 'fly') target.addScaledVector(forward, dolly);
    const offset = camera.position.clone().sub(target);
    const q = new THREE.Quaternion()
      .setFromAxisAngle(this.modeNow === 'trackball' ? up : new THREE.Vector3(0, 1, 0), m.yaw * dt)
      .multiply(new THREE.Quaternion().setFromAxisAngle(right, m.pitch * dt));
    offset.applyQuaternion(q);
    camera.position.copy(target).add(offset);
    if (this.modeNow === 'trackball') camera.up.applyQuaternion(q);
    camera.lookAt(target);
    this.viewer.requestRender();
  }
}

/** Whether a key goes to a form field (then it is no shortcut). */
export function typing(target: EventTarget | null): boolean {
  const t = target as HTMLElement | null;
  if (!t) return false;
  if (t.tagName === 'INPUT') return !['checkbox', 'radio', 'button', 'submit', 'range'].includes((t as HTMLInputElement).type);
  return t.tagName === 'TEXTAREA' || t.tagName === 'SELECT' || t.isContentEditable;
}

// The part of WebHID used here (TypeScript's DOM library has no types for it).
interface HidDevice {
  opened: boolean;
  productName: string;
  open(): Promise<void>;
  addEventListener(type: 'inputreport', listener: (e: HidInputReportEvent) => void): void;
}
interface HidInputReportEvent extends Event {
  reportId: number;
  data: DataView;
}
interface HidApi {
  requestDevice(options: { filters: Array<{ vendorId: number }> }): Promise<HidDevice[]>;
}
