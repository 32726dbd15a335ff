// The renderer for one kind of quantity: a point cloud (an uploaded cloud, a
// job's `points` artifact), drawn as round points of a size in pixels that
// stays the same at every zoom (as CloudCompare and Potree draw clouds by
// default). A point's colour is the file's where it has colours, shown as
// the file gives it (sRGB, untouched by the lights); with normals a point
// is shaded by how squarely it faces the camera (a headlight), so that a
// surface sampled by the cloud reads as one; without normals it is flat.
import * as THREE from 'three';
import type { DecodedColors } from './decoded_mesh.ts';
import type { DisplaySettings } from './display_modes.ts';

/** The palette of jobs' points drawn over their mesh, one colour each (kinds/points.ts). */
export const POINTS_PALETTE = ['#4fc3f7', '#aed581', '#f06292', '#ffd54f', '#ba68c8', '#4db6ac'] as const;
/** What a cloud is drawn from: positions, and normals and colours where it has them (a DecodedMesh of a Draco point cloud). */
export interface PointCloudData {
  positions: Float32Array;
  normals: Float32Array | null;
  colors: DecodedColors | null;
}

/**
 * How a cloud is drawn, from the Display panel's settings: the size in
 * pixels, the colour of points without one, whether the file's colours are
 * used.
 */
export type PointsLook = Pick<DisplaySettings, 'pointSize' | 'color' | 'vertexColors'>;

const vertexShader = /* glsl */ `
uniform float size;
uniform vec3 plain;
uniform float useColors;
varying vec3 vColor;
void main() {
  vec4 mv = modelViewMatrix * vec4(position, 1.0);
  gl_Position = projectionMatrix * mv;
  gl_PointSize = size;
  vec3 c = plain;
#if defined(USE_COLOR_ALPHA)
  c = mix(plain, color.rgb, useColors);
#elif defined(USE_COLOR)
  c = mix(plain, color, useColors);
#endif
#ifdef POINT_NORMALS
  // Facing the camera: full light; edge-on: a third. Both sides alike (a normal's sign is often arbitrary).
  float facing = abs(normalize(normalMatrix * normal).z);
  c *= 0.35 + 0.65 * facing;
#endif
  vColor = c;
}
`;

const fragmentShader = /* glsl */ `
varying vec3 vColor;
void main() {
  vec2 d = gl_PointCoord - vec2(0.5);
  if (dot(d, d) > 0.25) discard;
  gl_FragColor = vec4(vColor, 1.0);
}
`;

/** An sRGB hex colour as the shader writes it (no conversion: what is written is what is shown). */
function srgb(hex: string): THREE.Vector3 {
  const n = parseInt(hex.replace('#', ''), 16);
  return new THREE.Vector3(((n >> 16) & 255) / 255, ((n >> 8) & 255) / 255, (n & 255) / 255);
}

/** The device pixels of one CSS pixel, as the viewer renders (at most 2). */
function pixelRatio(): number {
  return Math.min(globalThis.devicePixelRatio || 1, 2);
}

/** A cloud as THREE.Points, drawn as `look` says; `name` names it in the scene ("points" for an uploaded cloud). */
export function buildPoints(cloud: PointCloudData, look: PointsLook, name = 'points'): THREE.Points {
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute('position', new THREE.BufferAttribute(cloud.positions, 3));
  if (cloud.normals) geometry.setAttribute('normal', new THREE.BufferAttribute(cloud.normals, 3));
  if (cloud.colors) geometry.setAttribute('color', new THREE.BufferAttribute(cloud.colors.array, cloud.colors.itemSize, cloud.colors.normalized));
  geometry.computeBoundingBox();
  geometry.computeBoundingSphere();
  const material = new THREE.ShaderMaterial({
    uniforms: { size: { value: 1 }, plain: { value: new THREE.Vector3() }, useColors: { value: 1 } },
    vertexShader,
    fragmentShader,
    vertexColors: cloud.colors !== null,
    defines: cloud.normals ? { POINT_NORMALS: '' } : {},
  });
  const points = new THREE.Points(geometry, material);
  points.name = name;
  points.userData.pointCloud = true;
  setPointsLook(points, look);
  return points;
}

/** Whether `object` is a cloud drawn by buildPoints (not the points of a surface drawn in the points mode). */
export function isPointCloud(object: THREE.Object3D | null): object is THREE.Points<THREE.BufferGeometry, THREE.ShaderMaterial> {
  return !!object && (object as THREE.Points).isPoints === true && object.userData.pointCloud === true;
}

/** Draws a cloud made by buildPoints as `look` says (the Display panel's point size and colour changed). */
export function setPointsLook(points: THREE.Points, look: PointsLook): void {
  const material = points.material as THREE.ShaderMaterial;
  material.uniforms.size!.value = look.pointSize * pixelRatio();
  (material.uniforms.plain!.value as THREE.Vector3).copy(srgb(look.color));
  material.uniforms.useColors!.value = look.vertexColors ? 1 : 0;
  points.userData.look = { pointSize: look.pointSize, color: look.color, vertexColors: look.vertexColors };
}

/** What a drawn cloud is, for the tests: its points, its size in pixels, whether it draws the file's colours and shades by normals. */
export function pointsReport(points: THREE.Points): { points: number; size: number; colors: boolean; normals: boolean } {
  const geometry = points.geometry;
  const look = points.userData.look as PointsLook;
  return {
    points: geometry.getAttribute('position').count,
    size: look.pointSize,
    colors: geometry.getAttribute('color') !== undefined && look.vertexColors,
    normals: geometry.getAttribute('normal') !== undefined,
  };
}
