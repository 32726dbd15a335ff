// The "Code" button of the top bar: shows and hides the code panel (a
// column beside the view, in place of the right sidebar, its width dragged
// at its left edge), loading it (the editor and the plugin controller: a
// chunk of their own) the first time it is shown.
import type { AppContext } from '../controllers/context.ts';
import type { PluginsController, PluginsDeps } from '../controllers/plugins.ts';
import { byId, el } from './dom.ts';
import './playground.css';

const MIN_WIDTH = 320;
/** The view keeps at least this much of the window beside the panel. */
const VIEW_MIN = 240;

/** The code panel, for those who open a file in it (the Course panel: a starter, a submission). */
export interface CodePanel {
  /** Shows the panel (loading it the first time): its controller, or null when it cannot be loaded. */
  open(): Promise<PluginsController | null>;
  /** Its controller, if it was ever shown; null otherwise. */
  loaded(): Promise<PluginsController | null> | null;
  /** Whether it is shown now. */
  isShown(): boolean;
  /** Calls `listener` when it is shown or hidden. */
  onShown(listener: (shown: boolean) => void): void;
}

export function installPlayground(ctx: AppContext, deps: PluginsDeps): CodePanel {
  const button = byId<HTMLButtonElement>('playground-toggle');
  const section = byId('playground');
  let loaded: Promise<PluginsController | null> | null = null;
  const listeners: Array<(shown: boolean) => void> = [];

  const handle = el('div', { class: 'playground-resize', role: 'separator', 'aria-orientation': 'vertical', 'aria-label': 'Resize the code panel', title: 'Drag to resize' });
  section.append(handle);
  handle.addEventListener('pointerdown', (down) => {
    down.preventDefault();
    handle.setPointerCapture(down.pointerId);
    const right = section.getBoundingClientRect().right;
    const layout = section.parentElement!;
    const move = (ev: PointerEvent): void => {
      const left = layout.getBoundingClientRect().left;
      const width = Math.round(Math.min(Math.max(MIN_WIDTH, right - ev.clientX), right - left - VIEW_MIN));
      layout.style.setProperty('--playground-width', `${width}px`);
    };
    const up = (): void => {
      handle.removeEventListener('pointermove', move);
      handle.removeEventListener('pointerup', up);
      handle.removeEventListener('pointercancel', up);
    };
    handle.addEventListener('pointermove', move);
    handle.addEventListener('pointerup', up);
    handle.addEventListener('pointercancel', up);
  });

  const show = (open: boolean): void => {
    section.hidden = !open;
    button.setAttribute('aria-pressed', String(open));
    if (open && !loaded) {
      const body = el('div', { class: 'playground-body' });
      section.prepend(body);
      loaded = import('../controllers/plugins.ts').then(
        (m) => new m.PluginsController(ctx, deps, body),
        (e: unknown) => {
          loaded = null;
          body.remove();
          ctx.error(`Cannot load the code panel: ${(e as Error).message}`);
          return null;
        },
      );
    } else if (open) {
      void loaded!.then((c) => c?.shown());
    }
    for (const listener of listeners) listener(open);
  };
  button.addEventListener('click', () => show(section.hidden));
  return {
    open: () => {
      if (section.hidden) show(true);
      return loaded ?? Promise.resolve(null);
    },
    loaded: () => loaded,
    isShown: () => !section.hidden,
    onShown: (listener) => void listeners.push(listener),
  };
}
