// Overlays over the shown surface: its bounding box with the box's
// dimensions written on its edges, axes sized to it with X/Y/Z labels,
// vertex and face normals (length a fraction of the box's diagonal), and
// its boundary edges (used by one triangle) and non-manifold edges (used by
// more than two) highlighted. Each is one of the viewer's named overlays,
// rebuilt when the shown object or the settings change. Labels are sprites
// (text drawn on a canvas texture), so they move with the view without any
// DOM to keep in step with the camera.
import * as THREE from 'three';
import { VertexNormalsHelper } from 'three/addons/helpers/VertexNormalsHelper.js';
import { formatNumber } from '../panels/format.ts';
import { classifyEdges, type EdgeClasses } from './mesh_edges.ts';
import { isPointCloud } from './points_renderer.ts';
import type { Viewer } from './viewer.ts';

export interface OverlaySettings {
  bbox: boolean;
  axes: boolean;
  vertexNormals: boolean;
  faceNormals: boolean;
  /** Normal length as a fraction of the bounding box's diagonal. */
  normalLength: number;
  /** Boundary and non-manifold edges. */
  edges: boolean;
}

export const DEFAULT_OVERLAYS: Readonly<OverlaySettings> = {
  bbox: false,
  axes: false,
  vertexNormals: false,
  faceNormals: false,
  normalLength: 0.03,
  edges: false,
};

export const EDGE_COLORS = { boundary: '#ff3b3b', nonManifold: '#ffd400' } as const;
const BOX_COLOR = '#d8dce6';
const VERTEX_NORMAL_COLOR = '#3fd0ff';
const FACE_NORMAL_COLOR = '#b6ff4a';

/** Settings from untrusted JSON (a view link): what is valid is taken, the rest is the default. */
export function sanitizeOverlays(raw: Record<string, unknown> | undefined): OverlaySettings {
  const s: OverlaySettings = { ...DEFAULT_OVERLAYS };
  if (!raw) return s;
  for (const k of ['bbox', 'axes', 'vertexNormals', 'faceNormals', 'edges'] as const) {
    if (typeof raw[k] === 'boolean') s[k] = raw[k];
  }
  const n = raw.normalLength;
  if (typeof n === 'number' && Number.isFinite(n)) s.normalLength = Math.min(0.2, Math.max(0.001, n));
  return s;
}

/** What the overlays found, for the panel's readout. */
export interface OverlayInfo {
  /** The bounding box's size (x, y, z); null when nothing is shown. */
  size: [number, number, number] | null;
  /** Counted only while the edge overlay is on (a large mesh takes a moment); null otherwise. */
  boundaryEdges: number | null;
  nonManifoldEdges: number | null;
}

/** "2 × 1 × 0.5": each side as every other number in the viewer is written (panels/format.ts). */
export function formatSize(size: [number, number, number]): string {
  return size.map(formatNumber).join(' × ');
}

/** A text label as a sprite `height` world units tall, drawn over everything. */
function label(text: string, color: string, height: number): THREE.Sprite {
  const canvas = document.createElement('canvas');
  const ctx = canvas.getContext('2d')!;
  const font = 'bold 48px system-ui, sans-serif';
  ctx.font = font;
  canvas.width = Math.ceil(ctx.measureText(text).width) + 16;
  canvas.height = 64;
  ctx.font = font; // resizing the canvas reset it
  ctx.textAlign = 'center';
  ctx.textBaseline = 'middle';
  ctx.lineWidth = 8;
  ctx.strokeStyle = 'rgba(20, 22, 26, 0.85)';
  ctx.strokeText(text, canvas.width / 2, 34);
  ctx.fillStyle = color;
  ctx.fillText(text, canvas.width / 2, 34);
  const texture = new THREE.CanvasTexture(canvas);
  texture.colorSpace = THREE.SRGBColorSpace;
  const material = new THREE.SpriteMaterial({ map: texture, depthTest: false, transparent: true });
  material.addEventListener('dispose', () => texture.dispose());
  const sprite = new THREE.Sprite(material);
  sprite.scale.set((height * canvas.width) / canvas.height, height, 1);
  sprite.renderOrder = 10;
  sprite.userData.text = text;
  return sprite;
}

function boundingBox(box: THREE.Box3, size: THREE.Vector3, textHeight: number): THREE.Object3D {
  const group = new THREE.Group();
  group.add(new THREE.Box3Helper(box, new THREE.Color(BOX_COLOR)));
  const { min, max } = box;
  const mid = box.getCenter(new THREE.Vector3());
  const at: Array<[number, THREE.Vector3]> = [
    [size.x, new THREE.Vector3(mid.x, min.y, max.z)],
    [size.y, new THREE.Vector3(max.x, mid.y, max.z)],
    [size.z, new THREE.Vector3(max.x, min.y, mid.z)],
  ];
  for (const [length, position] of at) {
    const sprite = label(formatNumber(length), BOX_COLOR, textHeight);
    sprite.position.copy(position);
    group.add(sprite);
  }
  return group;
}

/**
 * The object's own axes (`turn`: its world rotation), from `origin`: a mesh
 * drawn Z up has its Z axis drawn, and labelled, pointing up.
 */
function axes(origin: THREE.Vector3, length: number, textHeight: number, turn: THREE.Quaternion): THREE.Object3D {
  const group = new THREE.Group();
  const helper = new THREE.AxesHelper(length);
  helper.position.copy(origin);
  helper.quaternion.copy(turn);
  group.add(helper);
  const names: Array<[string, string, THREE.Vector3]> = [
    ['X', '#ff6b5b', new THREE.Vector3(1, 0, 0)],
    ['Y', '#7dff6b', new THREE.Vector3(0, 1, 0)],
    ['Z', '#6bb0ff', new THREE.Vector3(0, 0, 1)],
  ];
  for (const [name, color, dir] of names) {
    const sprite = label(name, color, textHeight);
    sprite.position.copy(origin).addScaledVector(dir.applyQuaternion(turn), length * 1.08);
    group.add(sprite);
  }
  return group;
}

/** Segments from each triangle's centroid along its normal. */
function faceNormals(geometry: THREE.BufferGeometry, length: number): THREE.LineSegments {
  const pos = geometry.getAttribute('position');
  const index = geometry.getIndex();
  const triangles = Math.floor((index ? index.count : pos.count) / 3);
  const out = new Float32Array(triangles * 6);
  const a = new THREE.Vector3();
  const b = new THREE.Vector3();
  const c = new THREE.Vector3();
  const n = new THREE.Triangle();
  const normal = new THREE.Vector3();
  const centroid = new THREE.Vector3();
  for (let t = 0; t < triangles; ++t) {
    const i = (k: number) => (index ? index.getX(3 * t + k) : 3 * t + k);
    a.fromBufferAttribute(pos, i(0));
    b.fromBufferAttribute(pos, i(1));
    c.fromBufferAttribute(pos, i(2));
    n.set(a, b, c);
    n.getNormal(normal);
    centroid
      .copy(a)
      .add(b)
      .add(c)
      .multiplyScalar(1 / 3);
    centroid.toArray(out, 6 * t);
    centroid.addScaledVector(normal, length).toArray(out, 6 * t + 3);
  }
  const g = new THREE.BufferGeometry();
  g.setAttribute('position', new THREE.BufferAttribute(out, 3));
  return new THREE.LineSegments(g, new THREE.LineBasicMaterial({ color: FACE_NORMAL_COLOR }));
}

/** Lines along the vertex pairs `pairs` of the geometry's positions. */
function edgeLines(positions: THREE.BufferAttribute | THREE.InterleavedBufferAttribute, pairs: Uint32Array, color: string): THREE.LineSegments {
  const out = new Float32Array(pairs.length * 3);
  for (let i = 0; i < pairs.length; ++i) {
    out[3 * i] = positions.getX(pairs[i]!);
    out[3 * i + 1] = positions.getY(pairs[i]!);
    out[3 * i + 2] = positions.getZ(pairs[i]!);
  }
  const g = new THREE.BufferGeometry();
  g.setAttribute('position', new THREE.BufferAttribute(out, 3));
  const lines = new THREE.LineSegments(g, new THREE.LineBasicMaterial({ color }));
  lines.renderOrder = 5;
  return lines;
}

/** The edge classes of a geometry, computed once per geometry. */
const edgeCache = new WeakMap<THREE.BufferGeometry, EdgeClasses>();

export function edgeClassesOf(geometry: THREE.BufferGeometry): EdgeClasses {
  let classes = edgeCache.get(geometry);
  if (!classes) {
    const pos = geometry.getAttribute('position');
    classes = classifyEdges(pos.array as ArrayLike<number>, geometry.getIndex()?.array ?? null);
    edgeCache.set(geometry, classes);
  }
  return classes;
}

/** `overlay` drawn with `mesh`'s world transform (it is not the mesh's child: the viewer owns overlays). */
function placed(overlay: THREE.Object3D, mesh: THREE.Object3D): THREE.Object3D {
  mesh.updateWorldMatrix(true, false);
  overlay.matrixAutoUpdate = false;
  overlay.matrix.copy(mesh.matrixWorld);
  return overlay;
}

export const OVERLAY_NAMES = ['bbox', 'axes', 'vertex-normals', 'face-normals', 'edges'] as const;

/**
 * Shows the overlays `s` asks for over `object` (the viewer's shown object;
 * null: none) in `viewer`, replacing the previous ones.
 */
export function updateOverlays(viewer: Viewer, object: THREE.Object3D | null, s: OverlaySettings): OverlayInfo {
  const info: OverlayInfo = { size: null, boundaryEdges: null, nonManifoldEdges: null };
  const built: Record<(typeof OVERLAY_NAMES)[number], THREE.Object3D | null> = {
    bbox: null,
    axes: null,
    'vertex-normals': null,
    'face-normals': null,
    edges: null,
  };
  const box = object ? new THREE.Box3().setFromObject(object) : new THREE.Box3();
  if (object && !box.isEmpty()) {
    const size = box.getSize(new THREE.Vector3());
    info.size = [size.x, size.y, size.z];
    const diagonal = Math.max(size.length(), 1e-9);
    const textHeight = diagonal * 0.05;
    if (s.bbox) built.bbox = boundingBox(box, size, textHeight);
    if (s.axes) {
      object.updateWorldMatrix(true, false);
      const turn = new THREE.Quaternion();
      object.matrixWorld.decompose(new THREE.Vector3(), turn, new THREE.Vector3());
      // From the corner of the object's own box, where its axes run along its edges (the world box's is another corner once it is turned).
      const geometry = (object as THREE.Mesh).isMesh ? (object as THREE.Mesh).geometry : null;
      if (geometry && !geometry.boundingBox) geometry.computeBoundingBox();
      const origin = geometry?.boundingBox ? geometry.boundingBox.min.clone().applyMatrix4(object.matrixWorld) : box.min;
      built.axes = axes(origin, Math.max(size.x, size.y, size.z) * 0.5, textHeight, turn);
    }
    const mesh = object as THREE.Mesh;
    const length = s.normalLength * diagonal;
    // A cloud's normals too (those it came with, or estimated by a job): what shades its points, shown.
    if (s.vertexNormals && (mesh.isMesh || isPointCloud(object)) && mesh.geometry.getAttribute('normal')) {
      built['vertex-normals'] = new VertexNormalsHelper(mesh, length, new THREE.Color(VERTEX_NORMAL_COLOR).getHex());
    }
    if (mesh.isMesh) {
      // Built in the mesh's own coordinates, placed where the mesh stands (a scene object moved, turned or scaled).
      const scale = Math.max(mesh.matrixWorld.getMaxScaleOnAxis(), 1e-9);
      if (s.faceNormals) built['face-normals'] = placed(faceNormals(mesh.geometry, length / scale), mesh);
      if (s.edges) {
        const classes = edgeClassesOf(mesh.geometry);
        info.boundaryEdges = classes.boundary.length / 2;
        info.nonManifoldEdges = classes.nonManifold.length / 2;
        const group = new THREE.Group();
        const pos = mesh.geometry.getAttribute('position');
        group.add(edgeLines(pos, classes.boundary, EDGE_COLORS.boundary), edgeLines(pos, classes.nonManifold, EDGE_COLORS.nonManifold));
        built.edges = placed(group, mesh);
      }
    }
  }
  for (const name of OVERLAY_NAMES) viewer.setOverlay(name, built[name]);
  return info;
}
