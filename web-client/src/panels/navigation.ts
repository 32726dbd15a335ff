// The navigation controls of the toolbar: the mode (orbit, trackball, fly),
// views along the axes (buttons, and keys 1 / 3 / 7 as Blender's numpad:
// front, right, top; with Shift or Ctrl the opposite side), reset (Home), and
// "3D mouse" (connect one) where the browser offers WebHID.
import { Navigation, typing, type AxisView, type NavigationMode } from '../viewer/navigation.ts';
import { el } from './dom.ts';

/** The axis views, as [button text, direction looked in, title]. */
const VIEWS: Array<[string, AxisView, string]> = [
  ['Front', '-z', 'Look along -Z (1)'],
  ['Back', '+z', 'Look along +Z (Shift+1)'],
  ['Right', '-x', 'Look along -X, from the right (3)'],
  ['Left', '+x', 'Look along +X, from the left (Shift+3)'],
  ['Top', '-y', 'Look down along -Y (7)'],
  ['Bottom', '+y', 'Look up along +Y (Shift+7)'],
];

const KEYS: Record<string, [AxisView, AxisView]> = {
  Digit1: ['-z', '+z'],
  Numpad1: ['-z', '+z'],
  Digit3: ['-x', '+x'],
  Numpad3: ['-x', '+x'],
  Digit7: ['-y', '+y'],
  Numpad7: ['-y', '+y'],
};

export class NavigationPanel {
  constructor(root: HTMLElement, navigation: Navigation, error: (text: string) => void) {
    const mode = el('select', { id: 'navigation-mode', 'aria-label': 'Navigation', title: 'How the mouse moves the camera' });
    for (const [value, text] of [
      ['orbit', 'Orbit'],
      ['trackball', 'Trackball'],
      ['fly', 'Fly (WASD)'],
    ])
      mode.append(el('option', { value }, text));
    mode.addEventListener('change', () => navigation.setMode(mode.value as NavigationMode));
    const views = el('span', { class: 'view-buttons' });
    for (const [text, axis, title] of VIEWS) {
      const b = el('button', { type: 'button', class: 'button small', 'data-view': axis, title }, text);
      b.addEventListener('click', () => navigation.viewAlong(axis));
      views.append(b);
    }
    const reset = el('button', { type: 'button', class: 'button small', id: 'view-reset', title: 'Frame the mesh again (Home)' }, 'Reset');
    reset.addEventListener('click', () => navigation.reset());
    root.replaceChildren(mode, views, reset);
    if (Navigation.hasHid()) {
      // A short label, so that the toolbar stays one row at 1280 px; the title says what it does.
      const connect = el(
        'button',
        { type: 'button', class: 'button small', id: 'connect-3d-mouse', title: 'Connect a 3D mouse: a 3Dconnexion SpaceMouse through WebHID' },
        '3D mouse',
      );
      connect.addEventListener('click', () => {
        navigation.connectSpaceMouse().then(
          (name) => {
            connect.textContent = name;
            connect.disabled = true;
          },
          (e: unknown) => error(`Cannot use the 3D mouse: ${e instanceof Error ? e.message : String(e)}`),
        );
      });
      root.append(connect);
    }
    window.addEventListener('keydown', (e) => {
      if (typing(e.target) || e.altKey || e.metaKey) return;
      if (e.code === 'Home') {
        navigation.reset();
        return;
      }
      const views = KEYS[e.code];
      if (!views) return;
      navigation.viewAlong(e.shiftKey || e.ctrlKey ? views[1] : views[0]);
      e.preventDefault();
    });
  }
}
