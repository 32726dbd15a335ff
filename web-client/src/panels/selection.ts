// The selection panel: the tool's switch, faces or vertices, box or lasso,
// visible only or through, grow / shrink / invert / clear, and the readout
// (count, the first ids, the area of the selected faces). A selection
// emptied by the user (Clear, a click on nothing, the other kind chosen)
// can be given back with the "Undo" its notice offers.
import type { UndoOffers } from '../controllers/undo.ts';
import type { SelectionState, SelectionTool } from '../viewer/selection_tool.ts';
import type { SelectionKind } from '../viewer/selection.ts';
import { typing } from '../viewer/navigation.ts';
import { el } from './dom.ts';
import { formatNumber, metricUnit, withUnit } from './format.ts';

const FIRST_IDS = 12;

export class SelectionPanel {
  private readonly readout: HTMLElement;
  private readonly toggle: HTMLButtonElement;
  private readonly tool: SelectionTool;
  private readonly root: HTMLElement;
  /** The selection as last rendered: an emptied one is offered back. */
  private last: Pick<SelectionState, 'meshId' | 'kind' | 'ids'> | null = null;

  /**
   * shortcut(): whether the S key may toggle the tool now (not in fly mode, where S moves back);
   * undo: offers an emptied selection back (none: it is gone).
   */
  constructor(
    root: HTMLElement,
    tool: SelectionTool,
    shortcut: () => boolean = () => true,
    private readonly undo: UndoOffers | null = null,
  ) {
    this.tool = tool;
    this.root = root;
    this.toggle = el('button', { type: 'button', class: 'button', id: 'select-tool', 'aria-pressed': 'false', title: 'Select with the mouse (S); the camera stays put' }, 'Select');
    this.toggle.addEventListener('click', () => this.setActive(!tool.active));

    const radio = <T extends string>(name: string, values: Array<[T, string]>, initial: T, set: (v: T) => void) => {
      const group = el('span', { class: 'segmented', role: 'radiogroup', 'aria-label': name });
      for (const [value, text] of values) {
        const id = `selection-${name}-${value}`;
        const input = el('input', { type: 'radio', name: `selection-${name}`, id, value });
        input.checked = value === initial;
        input.addEventListener('change', () => input.checked && set(value));
        group.append(input, el('label', { for: id }, text));
      }
      return group;
    };
    const kind = radio<SelectionKind>(
      'kind',
      [
        ['faces', 'Faces'],
        ['vertices', 'Vertices'],
      ],
      tool.kind,
      (v) => tool.setKind(v),
    );
    const shape = radio(
      'shape',
      [
        ['box', 'Box'],
        ['lasso', 'Lasso'],
      ],
      tool.shape,
      (v) => (tool.shape = v),
    );
    const through = el('input', { type: 'checkbox', id: 'selection-through' });
    through.addEventListener('change', () => (tool.through = through.checked));
    const button = (id: string, text: string, title: string, fn: () => void) => {
      const b = el('button', { type: 'button', class: 'button small', id, title }, text);
      b.addEventListener('click', fn);
      return b;
    };
    this.readout = el('div', { class: 'selection-readout', id: 'selection-readout', 'aria-live': 'polite' });
    root.replaceChildren(
      el('div', { class: 'selection-row' }, this.toggle, kind),
      el('div', { class: 'selection-row' }, shape, el('label', { class: 'check' }, through, ' Through (hidden too)')),
      el(
        'div',
        { class: 'selection-row' },
        button('selection-grow', 'Grow', 'One ring more', () => tool.grow()),
        button('selection-shrink', 'Shrink', 'One ring less', () => tool.shrink()),
        button('selection-invert', 'Invert', 'Select the others', () => tool.invert()),
        button('selection-clear', 'Clear', 'Select nothing', () => tool.clear()),
      ),
      this.readout,
      el('p', { class: 'hint' }, 'Click picks; drag a box or lasso. Shift adds, Ctrl subtracts.'),
    );
    this.render(tool.state());
    window.addEventListener('keydown', (e) => {
      if (e.key !== 's' || e.ctrlKey || e.metaKey || e.altKey || typing(e.target) || !shortcut()) return;
      this.setActive(!tool.active);
    });
  }

  setActive(on: boolean): void {
    this.tool.setActive(on);
    this.toggle.setAttribute('aria-pressed', String(on));
    this.toggle.classList.toggle('active', on);
    this.render(this.tool.state());
  }

  render(state: SelectionState): void {
    this.offerBack(state);
    const kind = this.root.querySelector<HTMLInputElement>(`#selection-kind-${state.kind}`);
    if (kind) kind.checked = true;
    const n = state.ids.length;
    if (!state.meshId || state.refused) {
      this.readout.replaceChildren(el('p', { class: 'empty' }, state.refused ?? 'Choose a mesh first.'));
      return;
    }
    const what = state.kind === 'faces' ? (n === 1 ? 'face' : 'faces') : n === 1 ? 'vertex' : 'vertices';
    const ids = state.ids.slice(0, FIRST_IDS).join(', ') + (n > FIRST_IDS ? ', …' : '');
    this.readout.replaceChildren(
      el('div', { class: 'selection-count', 'data-count': String(n) }, state.ready ? `${n} ${what}` : this.tool.active ? 'Loading…' : 'Press Select (S) to start.'),
    );
    if (n) this.readout.append(el('div', { class: 'selection-ids' }, `ids ${ids}`));
    if (state.area !== null && n)
      this.readout.append(el('div', { class: 'selection-area', title: `${state.area}` }, `${withUnit('area', metricUnit('area'))}: ${formatNumber(state.area)}`));
  }

  /** A selection of the same mesh emptied since the last render: a notice offers it back. */
  private offerBack(state: SelectionState): void {
    const last = this.last;
    this.last = { meshId: state.meshId, kind: state.kind, ids: state.ids };
    if (!this.undo || !last || !state.meshId || last.meshId !== state.meshId || !last.ids.length || state.ids.length) return;
    const n = last.ids.length;
    const what = last.kind === 'faces' ? (n === 1 ? 'face' : 'faces') : n === 1 ? 'vertex' : 'vertices';
    this.undo.offer(`Selection of ${n} ${what} cleared.`, {
      undo: () => {
        const now = this.tool.state();
        // Not over a selection made since, nor on another mesh.
        if (now.meshId !== last.meshId || now.ids.length) return;
        this.tool.setKind(last.kind);
        this.tool.select(last.ids);
      },
    });
  }
}
