// Messages shown in the page: errors stay until dismissed, notices fade. A
// message may carry an action, a button ("Undo") that runs it and dismisses
// the message.
import type { Message } from '../state/app_state.ts';
import { el } from './dom.ts';

const MAX_SHOWN = 5;

export class MessagesPanel {
  private readonly root: HTMLElement;

  constructor(root: HTMLElement) {
    this.root = root;
  }

  /** Shows a message of the state, with its action. */
  show(m: Message): void {
    this.add(m.level, m.text, m.level === 'error' ? 0 : (m.timeoutMs ?? 4000), m.action);
  }

  private add(kind: 'error' | 'notice', text: string, timeoutMs: number, action?: Message['action']): void {
    const close = el('button', { type: 'button', class: 'close', 'aria-label': 'Dismiss' }, '✕');
    const item = el('div', { class: `message ${kind}`, role: kind === 'error' ? 'alert' : 'status' }, el('span', { class: 'text' }, text));
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
    if (timeoutMs > 0) setTimeout(() => item.remove(), timeoutMs);
  }
}
