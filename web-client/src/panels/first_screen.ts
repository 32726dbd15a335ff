// The first screen: over an empty view, a card that says what to do (drop a
// mesh, pick one of the server's samples, upload one). It is gone while a
// mesh is shown and comes back when the scene is empty again; only the card
// itself takes the pointer, never the view around it.
import type { Mesh } from '../api/types.ts';
import { el } from './dom.ts';

/** The samples offered first where the server has them: small, quick to draw, known at a glance. */
const PREFERRED = ['elephant', 'bunny00', 'kitten', 'armadillo', 'camel'];
const OFFERED = 3;

/** The meshes the server loaded as samples (owned by "system"), the preferred ones first, at most three. */
export function samplesOf(meshes: readonly Mesh[]): Mesh[] {
  const rank = (m: Mesh) => {
    const i = PREFERRED.indexOf(sampleLabel(m));
    return i < 0 ? PREFERRED.length : i;
  };
  // The sort is stable: the others keep the list's order.
  return meshes
    .filter((m) => m.owner === 'system')
    .sort((a, b) => rank(a) - rank(b))
    .slice(0, OFFERED);
}

function sampleLabel(m: Mesh): string {
  return m.name.replace(/\.[^.]*$/, '') || m.name;
}

export interface FirstScreenActions {
  /** Shows the mesh (a sample picked). */
  show(id: string): void;
  /** Opens the file picker. */
  upload(): void;
}

export class FirstScreen {
  private readonly root = el('div', { class: 'first-screen' });
  private readonly title = el('h2', { class: 'first-screen-title', id: 'first-screen-title' });
  private readonly samples = el('div', { class: 'first-screen-samples' });
  private shownIds = '';

  constructor(
    viewport: HTMLElement,
    private readonly actions: FirstScreenActions,
  ) {
    const upload = el('button', { type: 'button', class: 'button first-screen-upload', title: 'Choose a mesh file to upload' }, 'Upload a mesh');
    upload.addEventListener('click', () => this.actions.upload());
    const card = el(
      'section',
      { class: 'first-screen-card', 'aria-labelledby': 'first-screen-title' },
      this.title,
      this.samples,
      upload,
      el('p', { class: 'first-screen-hint' }, 'OFF, OBJ, PLY, STL, Draco or glTF; a textured mesh as a zip with its MTL and images.'),
    );
    this.root.append(card);
    // First in the viewport, so that progress and messages are drawn over it.
    viewport.prepend(this.root);
    this.render([], false);
  }

  /** Shows the card (with buttons for `samples`) or hides it. */
  render(samples: readonly Mesh[], visible: boolean): void {
    this.root.hidden = !visible;
    const ids = samples.map((m) => m.id).join(' ');
    if (ids === this.shownIds && this.title.textContent) return;
    this.shownIds = ids;
    this.title.textContent = samples.length ? 'Drop a mesh here, or pick a sample' : 'Drop a mesh here';
    this.samples.hidden = samples.length === 0;
    this.samples.replaceChildren(
      ...samples.map((m) => {
        const button = el(
          'button',
          {
            type: 'button',
            class: 'button first-screen-sample',
            'data-mesh-id': m.id,
            title: `Show the sample ${m.name} (${m.report.vertices} vertices, ${m.report.faces} faces)`,
          },
          sampleLabel(m),
        );
        button.addEventListener('click', () => this.actions.show(m.id));
        return button;
      }),
    );
  }
}
