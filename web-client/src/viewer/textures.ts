// Textures on the shown surface: the mesh's own images (each material's map_Kd, or its PLY's
// TextureFile), none, or a checkerboard to inspect its UVs; and
// the small panel that picks one, shown only for a mesh with UVs. A mesh with
// UVs and no image gets the checkerboard, unless its UVs cannot show one
// (viewer/uv_check.ts): then the plain surface, and the panel says why.
import * as THREE from 'three';
import { fetchMeshTexture } from '../api/rest.ts';
import type { Mesh } from '../api/types.ts';
import { el } from '../panels/dom.ts';
import { withGroupLooks, type GroupLook } from './display_modes.ts';
import { uvProblem } from './uv_check.ts';

export type TextureMode = 'texture' | 'off' | 'checkerboard';

/** The checkerboard's two colours (sRGB): dark and light. */
export const CHECKER_DARK = '#202020';
export const CHECKER_LIGHT = '#f0f0f0';

/** A canvas of `squares` × `squares` alternating squares, repeating across the UV plane. */
export function checkerTexture(squares: number): THREE.CanvasTexture {
  const cell = 16;
  const canvas = document.createElement('canvas');
  canvas.width = canvas.height = squares * cell;
  const g = canvas.getContext('2d')!;
  for (let i = 0; i < squares; ++i) {
    for (let j = 0; j < squares; ++j) {
      g.fillStyle = (i + j) % 2 ? CHECKER_DARK : CHECKER_LIGHT;
      g.fillRect(i * cell, j * cell, cell, cell);
    }
  }
  const texture = new THREE.CanvasTexture(canvas);
  texture.colorSpace = THREE.SRGBColorSpace;
  texture.wrapS = texture.wrapT = THREE.RepeatWrapping;
  texture.magFilter = THREE.NearestFilter;
  return texture;
}

/**
 * A mesh's texture image as a three.js texture. OBJ and PLY put v = 0 at
 * the image's bottom row; an HTMLImageElement starts at the top, which
 * three.js's default flipY = true turns round.
 */
export async function loadMeshTexture(meshId: string, n: number, signal?: AbortSignal): Promise<THREE.Texture> {
  const blob = await fetchMeshTexture(meshId, n, signal);
  const url = URL.createObjectURL(blob);
  try {
    const img = new Image();
    img.src = url;
    await img.decode();
    const texture = new THREE.Texture(img);
    texture.colorSpace = THREE.SRGBColorSpace;
    texture.wrapS = texture.wrapT = THREE.RepeatWrapping;
    texture.flipY = true;
    texture.needsUpdate = true;
    return texture;
  } finally {
    URL.revokeObjectURL(url);
  }
}

/** Each material's Kd colour (no texture) on a surface with several materials, or null (none has a Kd, or vertex colours show). */
function colourLooks(mesh: Mesh, surface: THREE.Mesh, material: THREE.MeshStandardMaterial): GroupLook[] | null {
  const materials = mesh.materials ?? [];
  if (materials.length < 2 || surface.geometry.groups.length === 0 || material.vertexColors) return null;
  return materials.some((m) => m.kd) ? materials.map((m) => ({ map: null, color: m.kd })) : null;
}

/** What is drawn, for tests: set after the first frame that shows it. */
export interface TextureState {
  meshId: string;
  mode: TextureMode;
  /** Squares across the checkerboard texture. */
  squares: number;
  /** The image shown in 'texture' mode (the one on the most faces), or null. */
  image: string | null;
  /** How many materials the surface is drawn with (one per material of a mesh with several, in 'texture' mode). */
  materials: number;
  /** What is wrong with the UVs (uv_check.ts), as the panel says it; null: nothing. */
  uvProblem: string | null;
}

/**
 * Owns the texture panel and the textures of the shown surface. attach()
 * after each new surface; the image is fetched once per mesh.
 */
export class MeshTextures {
  private readonly select: HTMLSelectElement;
  private readonly squaresInput: HTMLInputElement;
  private readonly squaresValue: HTMLOutputElement;
  private readonly squaresRow: HTMLElement;
  private readonly note: HTMLElement;
  private problem: string | null = null;
  private surface: THREE.Mesh | null = null;
  private mesh: Mesh | null = null;
  private baseColor = new THREE.Color();
  private image: { meshId: string; textures: THREE.Texture[] } | null = null;
  private checker: { squares: number; texture: THREE.CanvasTexture } | null = null;
  private loading: AbortController | null = null;

  constructor(
    private readonly panel: HTMLElement,
    private readonly redraw: (onDrawn: () => void) => void,
    private readonly onShown: (state: TextureState | null) => void,
    private readonly onError: (text: string) => void,
  ) {
    this.select = el('select', { id: 'texture-mode', 'aria-label': 'Texture' });
    for (const [value, label] of [
      ['texture', 'on'],
      ['off', 'off'],
      ['checkerboard', 'checkerboard'],
    ] as const) {
      this.select.append(el('option', { value }, label));
    }
    this.squaresInput = el('input', { id: 'texture-squares', type: 'range', min: '2', max: '64', step: '2', value: '8' });
    this.squaresInput.setAttribute('aria-label', 'Squares');
    this.squaresValue = el('output', { class: 'slider-value', for: 'texture-squares' }, this.squaresInput.value);
    this.squaresRow = el('label', { class: 'texture-squares' }, 'Squares ', this.squaresInput, this.squaresValue);
    this.note = el('p', { class: 'texture-note', id: 'texture-note' });
    this.note.hidden = true;
    panel.replaceChildren(el('label', {}, 'Texture ', this.select), this.squaresRow, this.note);
    panel.hidden = true;
    this.select.addEventListener('change', () => this.apply());
    this.squaresInput.addEventListener('input', () => {
      this.squaresValue.value = this.squaresInput.value;
      this.apply();
    });
  }

  /** Takes a new surface of `mesh`: the panel shows when it has UVs, and its texture (or a checkerboard) goes on. */
  attach(surface: THREE.Mesh, mesh: Mesh): void {
    this.loading?.abort();
    this.loading = null;
    this.surface = surface;
    this.mesh = mesh;
    const material = (Array.isArray(surface.material) ? surface.material[0] : surface.material) as THREE.MeshStandardMaterial;
    const uv = surface.geometry.getAttribute('uv');
    const uvs = uv !== undefined;
    if (mesh.kd && !material.vertexColors) material.color.setRGB(mesh.kd[0], mesh.kd[1], mesh.kd[2], THREE.SRGBColorSpace);
    this.baseColor.copy(material.color);
    this.panel.hidden = !uvs;
    if (!uvs) {
      // No texture to show, but several materials still show their Kd colours.
      surface.userData.looks = colourLooks(mesh, surface, material);
      surface.material = withGroupLooks(material, surface.userData.looks as GroupLook[] | null, this.baseColor);
      this.onShown(null);
      return;
    }
    const hasImage = (mesh.textures?.length ?? 0) > 0;
    (this.select.options[0] as HTMLOptionElement).disabled = !hasImage;
    this.problem = uvProblem(uv.array, surface.geometry.index?.array ?? null);
    this.note.textContent = this.problem ?? '';
    this.note.hidden = this.problem === null;
    // The mesh's own image is shown whatever its UVs; the checkerboard only where it can show something.
    this.select.value = hasImage ? 'texture' : this.problem ? 'off' : 'checkerboard';
    this.apply();
  }

  /** Forgets the surface (it was replaced or cleared). */
  detach(): void {
    this.loading?.abort();
    this.loading = null;
    this.surface = null;
    this.panel.hidden = true;
    this.onShown(null);
  }

  private apply(): void {
    const surface = this.surface;
    const mesh = this.mesh;
    if (!surface || !mesh) return;
    const mode = this.select.value as TextureMode;
    const squares = Number(this.squaresInput.value);
    this.squaresRow.hidden = mode !== 'checkerboard';
    if (mode === 'texture' && this.image?.meshId !== mesh.id) {
      this.loading?.abort();
      const controller = new AbortController();
      this.loading = controller;
      Promise.all((mesh.textures ?? []).map((_, n) => loadMeshTexture(mesh.id, n, controller.signal)))
        .then((textures) => {
          if (controller.signal.aborted) {
            for (const t of textures) t.dispose();
            return;
          }
          for (const t of this.image?.textures ?? []) t.dispose();
          this.image = { meshId: mesh.id, textures };
          this.loading = null;
          this.apply();
        })
        .catch((e: unknown) => {
          if (controller.signal.aborted) return;
          this.onError(`Cannot load the texture of ${mesh.name}: ${e instanceof Error ? e.message : String(e)}`);
        });
      return;
    }
    let map: THREE.Texture | null = null;
    // One material again (the first of a per-material array), then one per material when there are looks.
    const current = surface.material;
    const material = (Array.isArray(current) ? current[0] : current) as THREE.MeshStandardMaterial;
    if (Array.isArray(current)) for (const m of current.slice(1)) m.dispose();
    let looks: GroupLook[] | null = null;
    if (mode === 'texture') {
      const textures = this.image!.textures;
      map = textures[0] ?? null;
      // Several materials (geometry groups from the worker): each its own texture or MTL colour.
      if ((mesh.materials?.length ?? 0) > 1 && surface.geometry.groups.length > 0) {
        looks = mesh.materials!.map((m) => ({ map: m.texture === null ? null : (textures[m.texture] ?? null), color: m.kd }));
      }
    }
    if (mode === 'off') looks = colourLooks(mesh, surface, material);
    if (mode === 'checkerboard') {
      if (this.checker?.squares !== squares) {
        this.checker?.texture.dispose();
        this.checker = { squares, texture: checkerTexture(squares) };
      }
      map = this.checker.texture;
    }
    // Kept on the surface too, so that the display modes that replace its material keep it (display_modes.ts).
    surface.userData.map = map;
    surface.userData.looks = looks;
    // Points and wireframe (a basic material) draw no texture.
    if (!(material as THREE.Material as THREE.MeshBasicMaterial).isMeshBasicMaterial) {
      material.map = map;
      // The image shows its own colours; without one the surface keeps its colour.
      if (map) material.color.set(0xffffff);
      else material.color.copy(this.baseColor);
      material.needsUpdate = true;
    }
    surface.material = withGroupLooks(material, looks, this.baseColor);
    const materials = Array.isArray(surface.material) ? surface.material.length : 1;
    const image = mode === 'texture' ? (mesh.textures?.[0]?.name ?? null) : null;
    this.redraw(() => {
      if (this.surface === surface && surface.userData.map === map) this.onShown({ meshId: mesh.id, mode, squares, image, materials, uvProblem: this.problem });
    });
  }
}
