// The Scene panel: one row per object of the scene (the shown mesh first,
// then the meshes added with "+" in the mesh list): its name, a visibility
// box, a colour swatch, its transform (translation x/y/z, rotation x/y/z in
// degrees, uniform scale) and a remove button; "Fit all" frames every
// visible object, "Side by side" draws each in its own pane. A click on an
// object's name chooses it for the Display panel's overlays. A job's result
// added to the view has "Beside" and "In place": beside its source, or over
// it to compare. The app owns the scene (app.ts); the panel shows it and
// reports edits.
import type { SceneObjectState, Vec3 } from '../viewer/scene_state.ts';
import { el } from './dom.ts';

/** Where a result stands: over its source, beside it, or elsewhere (moved by hand). */
export type Placement = 'in place' | 'beside' | 'moved';

export interface SceneRow extends SceneObjectState {
  name: string;
  /** A job's result: its source's name, and where it stands against it. */
  source?: string;
  placement?: Placement;
}

export interface SceneActions {
  /** Object `index` changed (one field or several). */
  change(index: number, patch: Partial<SceneObjectState>): void;
  /** Removes object `index` (never the first: another mesh replaces it with a click). */
  remove(index: number): void;
  fitAll(): void;
  /** Object `index` is chosen (its overlays are drawn). */
  pick(index: number): void;
  /** The objects side by side (true) or together (false). */
  sideBySide(on: boolean): void;
  /** Result `index` over its source ("in place") or beside it. */
  place(index: number, where: Exclude<Placement, 'moved'>): void;
}

function numberInput(cls: string, value: number, step: string, label: string): HTMLInputElement {
  return el('input', { type: 'number', class: `scene-num ${cls}`, step, value: String(value), 'aria-label': label, title: label });
}

export class ScenePanel {
  private readonly list = el('ol', { class: 'scene-list', id: 'scene-list' });
  private readonly fitAll = el('button', { type: 'button', class: 'button small', id: 'scene-fit-all', title: 'Frame every visible object' }, 'Fit all');
  private readonly sideBySide = el('button', { type: 'button', class: 'button small', id: 'scene-side-by-side', title: 'Each object in its own pane, one camera' }, 'Side by side');
  private panes = false;

  constructor(
    root: HTMLElement,
    private readonly actions: SceneActions,
  ) {
    this.fitAll.addEventListener('click', () => this.actions.fitAll());
    this.sideBySide.addEventListener('click', () => this.actions.sideBySide(!this.panes));
    root.append(this.list, el('div', { class: 'scene-buttons' }, this.fitAll, this.sideBySide));
    this.render([], false, '');
  }

  /** Shows the rows; `materialColor` is the swatch of an object without its own colour. */
  render(rows: readonly SceneRow[], panes: boolean, materialColor: string, picked = 0): void {
    this.panes = panes;
    this.sideBySide.classList.toggle('active', panes);
    this.sideBySide.setAttribute('aria-pressed', String(panes));
    this.sideBySide.disabled = rows.length < 2 && !panes;
    this.fitAll.disabled = rows.length === 0;
    if (rows.length === 0) {
      this.list.replaceChildren(el('li', { class: 'empty' }, 'Click a mesh to show it; “+” adds it beside the others.'));
      return;
    }
    this.list.replaceChildren(...rows.map((row, i) => this.row(row, i, materialColor, i === picked)));
  }

  private row(row: SceneRow, index: number, materialColor: string, picked: boolean): HTMLLIElement {
    const change = (patch: Partial<SceneObjectState>) => this.actions.change(index, patch);
    const visible = el('input', { type: 'checkbox', class: 'scene-visible', title: `Show ${row.name}`, 'aria-label': `Show ${row.name}` });
    visible.checked = row.visible;
    visible.addEventListener('change', () => change({ visible: visible.checked }));
    const color = el('input', { type: 'color', class: 'scene-color', value: row.color ?? materialColor, title: `Colour of ${row.name}`, 'aria-label': `Colour of ${row.name}` });
    color.addEventListener('input', () => change({ color: color.value }));
    const vec = (cls: string, v: Vec3, step: string, what: string, key: 'position' | 'rotation') => {
      const inputs = v.map((x, k) => numberInput(`${cls}-${'xyz'[k]}`, x, step, `${what} ${'xyz'[k]}`));
      const read = () => {
        const values = inputs.map((input) => Number(input.value));
        if (values.every((x) => input_ok(x))) change({ [key]: values as Vec3 });
      };
      for (const input of inputs) input.addEventListener('change', read);
      return el('div', { class: 'scene-vec' }, el('span', { class: 'scene-vec-label' }, what), ...inputs);
    };
    const scale = numberInput('scene-scale', row.scale, '0.1', 'Scale');
    scale.min = '0.001';
    scale.addEventListener('change', () => {
      const s = Number(scale.value);
      if (input_ok(s) && s > 0) change({ scale: s });
    });
    const remove = el('button', { type: 'button', class: 'scene-remove', title: `Remove ${row.name} from the scene`, 'aria-label': `Remove ${row.name} from the scene` }, '✕');
    remove.hidden = index === 0;
    remove.addEventListener('click', () => this.actions.remove(index));
    const name = el('button', { type: 'button', class: 'scene-name', title: `${row.name}: click for its overlays` }, row.name);
    name.addEventListener('click', () => this.actions.pick(index));
    return el(
      'li',
      { class: picked ? 'scene-object picked' : 'scene-object', 'data-index': String(index), 'data-mesh-id': row.mesh },
      el('div', { class: 'scene-head' }, visible, color, name, remove),
      row.source === undefined ? null : this.placeButtons(row, index),
      vec('scene-t', row.position, '0.1', 'Move', 'position'),
      vec('scene-r', row.rotation, '5', 'Turn°', 'rotation'),
      el('div', { class: 'scene-vec' }, el('span', { class: 'scene-vec-label' }, 'Scale'), scale),
    );
  }

  private placeButtons(row: SceneRow, index: number): HTMLElement {
    const button = (where: Exclude<Placement, 'moved'>, label: string, title: string) => {
      const b = el('button', { type: 'button', class: 'button small scene-place', 'data-place': where, title, 'aria-pressed': String(row.placement === where) }, label);
      b.classList.toggle('active', row.placement === where);
      b.addEventListener('click', () => this.actions.place(index, where));
      return b;
    };
    return el(
      'div',
      { class: 'scene-placement', role: 'group', 'aria-label': `Where ${row.name} stands` },
      button('beside', 'Beside', `${row.name} beside ${row.source}`),
      button('in place', 'In place', `${row.name} over ${row.source}, to compare`),
    );
  }
}

const input_ok = (x: number) => Number.isFinite(x);
