// Display modes of the shown surface: points, wireframe, flat, smooth,
// hidden-line (the wireframe over the shaded surface) and toon (banded
// shading with outlines), with a material (presets, colour, roughness,
// metalness) and vertex colours on or off. A mode replaces the mesh's
// material and adds what it draws beside the faces as children of the mesh
// that share its geometry (the points, the lines, the outline), so that the
// viewer's disposal of the shown object frees them too. A scalar field's
// surface keeps its colours in every mode. A textured surface (its texture
// or the UV checkerboard in userData.map, set by viewer/textures.ts) keeps it
// in the shaded modes (smooth, flat, hidden-line, toon); points and wireframe
// draw the plain colour.
//
// Smooth shading (and the hidden-line and toon modes, which shade as it does)
// splits the normals where faces meet at more than the crease angle
// (viewer/crease.ts), so that a part's edges stay sharp; 180° averages them
// across every edge.
//
// Toon outlines are an inverted hull (the back faces of the surface pushed
// out along the normals, drawn black) rather than three's OutlineEffect: one
// extra draw, no second pass over the scene, and it renders the same in
// SwiftShader as on a GPU.
import * as THREE from 'three';
import { setCrease } from './crease.ts';
import { SURFACE_COLOR } from './surface_renderer.ts';

export const DISPLAY_MODES = ['smooth', 'flat', 'wireframe', 'points', 'hidden-line', 'toon'] as const;
export type DisplayMode = (typeof DISPLAY_MODES)[number];

export interface MaterialPreset {
  name: string;
  color: string;
  roughness: number;
  metalness: number;
}

/** Material presets; "default" is the surface renderer's own material. */
export const MATERIAL_PRESETS: readonly MaterialPreset[] = [
  { name: 'default', color: SURFACE_COLOR, roughness: 0.6, metalness: 0 },
  { name: 'plastic', color: '#d23c2a', roughness: 0.3, metalness: 0 },
  { name: 'metal', color: '#c9ccd2', roughness: 0.3, metalness: 1 },
  { name: 'gold', color: '#e0b04a', roughness: 0.25, metalness: 1 },
  { name: 'clay', color: '#b9826a', roughness: 1, metalness: 0 },
  { name: 'ceramic', color: '#f1ede4', roughness: 0.1, metalness: 0 },
];

export interface DisplaySettings {
  mode: DisplayMode;
  /** The preset last chosen (colour, roughness and metalness may have been changed since). */
  preset: string;
  /** sRGB hex colour of the surface (when it is not coloured per vertex). */
  color: string;
  roughness: number;
  metalness: number;
  /** Use the mesh's own vertex colours when it has some (a field's colours are always used). */
  vertexColors: boolean;
  /** Point size in pixels (points mode). */
  pointSize: number;
  /** Bands of the toon shading. */
  toonBands: number;
  /**
   * Degrees: faces meeting at more than this are shaded apart (smooth,
   * hidden-line and toon modes); 180 averages the normals across every edge.
   */
  creaseAngle: number;
}

/** The modes whose shading the crease angle changes. */
export const CREASED_MODES: readonly DisplayMode[] = ['smooth', 'hidden-line', 'toon'];

export const DEFAULT_DISPLAY: Readonly<DisplaySettings> = {
  mode: 'smooth',
  preset: 'default',
  color: SURFACE_COLOR,
  roughness: 0.6,
  metalness: 0,
  vertexColors: true,
  pointSize: 3,
  toonBands: 3,
  // three's own default: a CAD part's 90° edges (fandisk's) are sharp, a scan's noise (armadillo's) and a
  // coarse smooth mesh (eight.off, up to 49° between faces) stay smooth.
  creaseAngle: 60,
};

export function isDefaultDisplay(s: DisplaySettings): boolean {
  return (Object.keys(DEFAULT_DISPLAY) as Array<keyof DisplaySettings>).every((k) => s[k] === DEFAULT_DISPLAY[k]);
}

const clamp = (v: number, lo: number, hi: number) => Math.min(hi, Math.max(lo, v));

/** Settings from untrusted JSON (a view link): what is valid is taken, the rest is the default. */
export function sanitizeDisplay(raw: Record<string, unknown> | undefined): DisplaySettings {
  const s: DisplaySettings = { ...DEFAULT_DISPLAY };
  if (!raw) return s;
  const num = (v: unknown, lo: number, hi: number, d: number) => (typeof v === 'number' && Number.isFinite(v) ? clamp(v, lo, hi) : d);
  if (DISPLAY_MODES.includes(raw.mode as DisplayMode)) s.mode = raw.mode as DisplayMode;
  if (MATERIAL_PRESETS.some((p) => p.name === raw.preset)) s.preset = raw.preset as string;
  if (typeof raw.color === 'string' && /^#[0-9a-fA-F]{6}$/.test(raw.color)) s.color = raw.color.toLowerCase();
  s.roughness = num(raw.roughness, 0, 1, s.roughness);
  s.metalness = num(raw.metalness, 0, 1, s.metalness);
  if (typeof raw.vertexColors === 'boolean') s.vertexColors = raw.vertexColors;
  s.pointSize = num(raw.pointSize, 1, 20, s.pointSize);
  s.toonBands = Math.round(num(raw.toonBands, 2, 8, s.toonBands));
  s.creaseAngle = num(raw.creaseAngle, 0, 180, s.creaseAngle);
  return s;
}

/** The colours of the hidden-line wireframe and the toon outline. */
const LINE_COLOR = '#15171b';

/**
 * A gradient map of `bands` equal steps of light for MeshToonMaterial
 * (nearest filtering keeps the steps sharp). The steps stay well below 1:
 * the viewer's key light alone is 2.4, and steps that all saturate show no
 * bands.
 */
function toonGradient(bands: number): THREE.DataTexture {
  const data = new Uint8Array(bands);
  for (let i = 0; i < bands; ++i) data[i] = Math.round(255 * (0.08 + (0.4 * i) / (bands - 1)));
  const texture = new THREE.DataTexture(data, bands, 1, THREE.RedFormat);
  texture.minFilter = THREE.NearestFilter;
  texture.magFilter = THREE.NearestFilter;
  texture.generateMipmaps = false;
  texture.needsUpdate = true;
  return texture;
}

/** The inverted hull: back faces pushed out along the normals by `thickness`, in one flat colour. */
function outlineMaterial(thickness: number): THREE.ShaderMaterial {
  return new THREE.ShaderMaterial({
    uniforms: { thickness: { value: thickness }, color: { value: new THREE.Color(LINE_COLOR) } },
    vertexShader: /* glsl */ `
      uniform float thickness;
      void main() {
        vec3 p = position + normalize(normal) * thickness;
        gl_Position = projectionMatrix * modelViewMatrix * vec4(p, 1.0);
      }`,
    fragmentShader: /* glsl */ `
      uniform vec3 color;
      void main() { gl_FragColor = vec4(color, 1.0); }`,
    side: THREE.BackSide,
  });
}

/** A child drawn with the mesh's geometry; it takes no picks (rays hit the surface itself). */
function decoration(object: THREE.Object3D): THREE.Object3D {
  object.userData.display = true;
  object.raycast = () => {};
  return object;
}

/** Removes what a previous mode added to `mesh` (their materials and textures freed, the geometry is the mesh's). */
function clearDecorations(mesh: THREE.Mesh): void {
  for (const child of [...mesh.children]) {
    if (!child.userData.display) continue;
    mesh.remove(child);
    disposeMaterial((child as THREE.Mesh).material);
  }
}

function disposeMaterial(material: THREE.Material | THREE.Material[] | undefined): void {
  for (const m of Array.isArray(material) ? material : material ? [material] : []) {
    const toon = m as THREE.MeshToonMaterial;
    if (toon.isMeshToonMaterial) toon.gradientMap?.dispose();
    m.dispose();
  }
}

/** The texture on a textured surface (viewer/textures.ts keeps it in userData.map), or null. */
export function textureMap(mesh: THREE.Object3D): THREE.Texture | null {
  const map = mesh.userData.map as THREE.Texture | null | undefined;
  return map && map.isTexture ? map : null;
}

/** How one material's faces look: its texture, else its MTL colour (sRGB 0..1), else the surface's colour. */
export interface GroupLook {
  map: THREE.Texture | null;
  color: [number, number, number] | null;
}

/** The per-material looks of a surface with several materials (viewer/textures.ts keeps them in userData.looks), or null. */
export function groupLooks(mesh: THREE.Object3D): GroupLook[] | null {
  const looks = mesh.userData.looks as GroupLook[] | null | undefined;
  return looks && looks.length > 0 ? looks : null;
}

/**
 * `material` as one material per geometry group, each with its look's texture
 * or colour (`fallback` for a material with neither); `material` itself when
 * there are no looks or it draws no texture (wireframe, points). A replaced
 * `material` is disposed.
 */
export function withGroupLooks(material: THREE.Material, looks: GroupLook[] | null, fallback: THREE.Color): THREE.Material | THREE.Material[] {
  const textured = material as THREE.MeshStandardMaterial;
  if (!looks || !('map' in textured) || (material as THREE.MeshBasicMaterial).isMeshBasicMaterial) return material;
  const out = looks.map((look) => {
    const m = textured.clone();
    m.map = look.map;
    if (look.map) m.color.set(0xffffff);
    else if (look.color) m.color.setRGB(look.color[0], look.color[1], look.color[2], THREE.SRGBColorSpace);
    else m.color.copy(fallback);
    return m;
  });
  material.dispose();
  return out;
}

/** Whether the object is a surface that display modes apply to (not points, lines or a group). */
export function isSurface(object: THREE.Object3D | null): object is THREE.Mesh {
  return !!object && (object as THREE.Mesh).isMesh === true;
}

/**
 * Draws `mesh` in the mode and material of `s`. `environment` gives the
 * reflections metals need (asked for only when metalness > 0).
 */
export function applyDisplay(mesh: THREE.Mesh, s: DisplaySettings, environment: () => THREE.Texture | null): void {
  clearDecorations(mesh);
  const geometry = mesh.geometry;
  const hasColors = geometry.getAttribute('color') !== undefined;
  const isField = mesh.name.startsWith('scalar:');
  const vertexColors = hasColors && (isField || s.vertexColors);
  const color = new THREE.Color(vertexColors ? 0xffffff : s.color);
  const map = textureMap(mesh);
  // The image shows its own colours (as viewer/textures.ts draws it).
  const shaded = { color: map ? new THREE.Color(0xffffff) : color, map };
  const lit = {
    ...shaded,
    vertexColors,
    roughness: s.roughness,
    metalness: s.metalness,
    envMap: s.metalness > 0 ? environment() : null,
    side: THREE.DoubleSide,
  };
  let material: THREE.Material;
  switch (s.mode) {
    case 'smooth':
    case 'flat':
      material = new THREE.MeshStandardMaterial({ ...lit, flatShading: s.mode === 'flat' });
      break;
    case 'hidden-line': {
      // The faces pushed back in depth a little, so that the lines on them win the depth test.
      material = new THREE.MeshStandardMaterial({ ...lit, polygonOffset: true, polygonOffsetFactor: 1, polygonOffsetUnits: 1 });
      const lines = new THREE.Mesh(geometry, new THREE.MeshBasicMaterial({ color: LINE_COLOR, wireframe: true }));
      mesh.add(decoration(lines));
      break;
    }
    case 'wireframe':
      material = new THREE.MeshBasicMaterial({ color, vertexColors, wireframe: true });
      break;
    case 'points': {
      // The faces are not drawn (an invisible material still lets the children draw).
      material = new THREE.MeshBasicMaterial({ visible: false });
      const points = new THREE.Points(geometry, new THREE.PointsMaterial({ color, vertexColors, size: s.pointSize, sizeAttenuation: false }));
      mesh.add(decoration(points));
      break;
    }
    case 'toon': {
      material = new THREE.MeshToonMaterial({ ...shaded, vertexColors, gradientMap: toonGradient(s.toonBands), side: THREE.DoubleSide });
      if (!geometry.boundingSphere) geometry.computeBoundingSphere();
      const thickness = (geometry.boundingSphere?.radius ?? 1) * 0.008;
      mesh.add(decoration(new THREE.Mesh(geometry, outlineMaterial(thickness))));
      break;
    }
  }
  disposeMaterial(mesh.material);
  // Several materials: each group keeps its own texture or colour.
  mesh.material = withGroupLooks(material, groupLooks(mesh), color);
  applyCrease(mesh, s);
}

/** Splits the normals of `mesh` at the crease angle in the modes it applies to, or draws it as built. */
export function applyCrease(mesh: THREE.Mesh, s: DisplaySettings): void {
  setCrease(mesh, CREASED_MODES.includes(s.mode) ? s.creaseAngle : null);
}
