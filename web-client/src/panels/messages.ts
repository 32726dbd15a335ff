// Messages shown in the page. Notices go by themselves (warnings stay longer,
// to be read); errors stay until dismissed, since they ask the user to do
// something. A message may carry an action, a button ("Undo") that runs it
// and dismisses the message; such a message lasts as long as its offer.
// The stack sits outside the 3D view (app.ts places it), so that it never
// hides what the user is looking at.
import type { Message } from '../state/app_state.ts';
import { el } from './dom.ts';

const MAX_SHOWN = 5;

export type MessageLevel = Message['level'];

/** How long a message of each level stays by itself; 0: until dismissed. */
export const LINGER_MS: Record<MessageLevel, number> = { notice: 5000, warning: 10_000, error: 0 };

export class MessagesPanel {
  private readonly root: HTMLElement;

  constructor(root: HTMLElement) {
    this.root = root;
  }

  /** Shows a message of the state, with its action. */
  show(m: Message): void {
    // The same words again (a retry that fails again) replace the old message rather than stack up; an offer is its own.
    if (!m.action) {
      for (const old of this.root.querySelectorAll<HTMLElement>(`.message.${m.level}:not(:has(.message-action))`)) {
        if (old.querySelector('.text')?.textContent === m.text) old.remove();
      }
    }
    const close = el('button', { type: 'button', class: 'close', 'aria-label': 'Dismiss', title: 'Dismiss' }, '✕');
    const item = el('div', { class: `message ${m.level}`, role: m.level === 'error' ? 'alert' : 'status' }, el('span', { class: 'text' }, m.text));
    const action = m.action;
    if (action) {
      const button = el('button', { type: 'button', class: 'button small message-action' }, action.label);
      button.addEventListener('click', () => {
        item.remove();
        action.run();
      });
      item.append(button);
    }
    item.append(close);
    close.addEventListener('click', () => item.remove());
    this.root.append(item);
    while (this.root.children.length > MAX_SHOWN) this.root.firstElementChild!.remove();
    const lingerMs = m.level === 'error' ? 0 : (m.timeoutMs ?? LINGER_MS[m.level]);
    if (lingerMs > 0) setTimeout(() => item.remove(), lingerMs);
  }
}
