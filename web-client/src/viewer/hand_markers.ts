// The hands raised in a lecture, drawn over the view: a dot at the point
// each follower picked on a mesh and their name beside it, as HTML labels
// placed after every frame (never in the canvas: a screenshot of the view
// is the view alone). Picking the point: a ray from the camera through the
// pointer onto the surfaces shown, the point kept in the mesh's own
// coordinates, so that it lands on the same spot of the same mesh in every
// viewer whatever turns it.
import * as THREE from 'three';
import { el } from '../panels/dom.ts';
import type { Viewer } from './viewer.ts';

type Vec3 = [number, number, number];

/** A hand to draw: whose, where (a mesh and a point in its coordinates), and whether it is the one shown to all. */
export interface HandMark {
  user: string;
  mesh: string;
  position: Vec3;
  shown: boolean;
}

/** Finds the object that draws a mesh, by the mesh's id (null: not drawn). */
export type ObjectOfMesh = (mesh: string) => THREE.Object3D | null;

export class HandMarkers {
  private readonly viewer: Viewer;
  private readonly objectOf: ObjectOfMesh;
  private readonly layer: HTMLElement;
  private marks: Array<HandMark & { node: HTMLElement }> = [];

  constructor(container: HTMLElement, viewer: Viewer, objectOf: ObjectOfMesh) {
    this.viewer = viewer;
    this.objectOf = objectOf;
    this.layer = el('div', { class: 'hand-markers', 'aria-label': 'Raised hands' });
    container.append(this.layer);
  }

  /** The hands to draw (none: the layer is empty). */
  set(marks: readonly HandMark[]): void {
    this.marks = marks.map((m) => {
      const node = el(
        'div',
        { class: 'hand-marker', 'data-user': m.user, title: `${m.user}'s hand` },
        el('span', { class: 'hand-dot' }),
        el('span', { class: 'hand-name' }, m.user),
      );
      node.classList.toggle('shown', m.shown);
      return { ...m, node };
    });
    this.layer.replaceChildren(...this.marks.map((m) => m.node));
    this.place();
  }

  /** Places the labels where their points are now (after each frame). */
  place(): void {
    const canvas = this.viewer.renderer.domElement;
    const width = canvas.clientWidth;
    const height = canvas.clientHeight;
    for (const m of this.marks) {
      const object = this.objectOf(m.mesh);
      const p = object ? object.localToWorld(new THREE.Vector3(...m.position)) : null;
      let rect = { x: 0, y: 0, width, height };
      const pane = object ? this.viewer.paneOf(object) : -1;
      const r = pane >= 0 ? this.viewer.paneRect(pane) : null;
      if (r) rect = { x: r.x, y: height - r.y - r.height, width: r.width, height: r.height };
      const ndc = p?.project(this.viewer.camera);
      const visible = !!ndc && object!.visible && Math.abs(ndc.x) <= 1 && Math.abs(ndc.y) <= 1 && ndc.z <= 1;
      m.node.hidden = !visible;
      if (!visible) continue;
      m.node.style.left = `${rect.x + ((ndc.x + 1) / 2) * rect.width}px`;
      m.node.style.top = `${rect.y + ((1 - ndc.y) / 2) * rect.height}px`;
    }
  }
}

/**
 * The point of a surface drawn at (x, y), CSS pixels from the canvas's top
 * left: which of `objects` (each a mesh's, with its id) and where, in that
 * mesh's coordinates; null where no surface is drawn.
 */
export function pickPoint(viewer: Viewer, objects: ReadonlyArray<{ mesh: string; object: THREE.Object3D }>, x: number, y: number): { mesh: string; position: Vec3 } | null {
  const canvas = viewer.renderer.domElement;
  const height = canvas.clientHeight;
  let best: { mesh: string; position: Vec3; distance: number } | null = null;
  for (const { mesh, object } of objects) {
    if (!object.visible) continue;
    const pane = viewer.paneOf(object);
    const r = pane >= 0 ? viewer.paneRect(pane) : null;
    const rect = r ? { x: r.x, y: height - r.y - r.height, width: r.width, height: r.height } : { x: 0, y: 0, width: canvas.clientWidth, height };
    if (x < rect.x || y < rect.y || x > rect.x + rect.width || y > rect.y + rect.height) continue;
    const ndc = new THREE.Vector2(((x - rect.x) / rect.width) * 2 - 1, 1 - ((y - rect.y) / rect.height) * 2);
    const ray = new THREE.Raycaster();
    ray.setFromCamera(ndc, viewer.camera);
    const hit = ray.intersectObject(object, true).find((h) => (h.object as THREE.Mesh).isMesh);
    if (!hit || (best && best.distance <= hit.distance)) continue;
    best = { mesh, position: object.worldToLocal(hit.point.clone()).toArray() as Vec3, distance: hit.distance };
  }
  return best && { mesh: best.mesh, position: best.position };
}
