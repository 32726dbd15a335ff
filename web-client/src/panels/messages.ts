// Messages shown in the page. Notices go by themselves (warnings stay longer,
// to be read); errors stay until dismissed, since they ask the user to do
// something. A message may carry an action, a button ("Undo") that runs it
// and dismisses the message; such a message lasts as long as its offer.
// A message may name its topic ("a job of simplify on this mesh failed"): a
// newer one of the topic replaces it, and dismiss(topic) takes it away once
// it no longer holds (the rerun succeeded). The newest is on top and a few
// at most are shown, so that they never pile up over the sidebar's lists.
// The stack sits outside the 3D view (app.ts places it), so that it never
// hides what the user is looking at.
import type { Message } from '../state/app_state.ts';
import { el } from './dom.ts';

/** How many messages show at once: the oldest go first. */
export const MAX_SHOWN = 3;

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
    if (m.topic) this.dismiss(m.topic);
    // The same words again (a retry that fails again) replace the old message rather than stack up; an offer is its own.
    if (!m.action) {
      for (const old of this.root.querySelectorAll<HTMLElement>(`.message.${m.level}:not(:has(.message-action))`)) {
        if (old.querySelector('.text')?.textContent === m.text) old.remove();
      }
    }
    const close = el('button', { type: 'button', class: 'close', 'aria-label': 'Dismiss', title: 'Dismiss' }, '✕');
    const item = el('div', { class: `message ${m.level}`, role: m.level === 'error' ? 'alert' : 'status' }, el('span', { class: 'text' }, m.text));
    if (m.topic) item.dataset.topic = m.topic;
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
    this.root.prepend(item);
    while (this.root.children.length > MAX_SHOWN) this.root.lastElementChild!.remove();
    const lingerMs = m.level === 'error' ? 0 : (m.timeoutMs ?? LINGER_MS[m.level]);
    if (lingerMs > 0) setTimeout(() => item.remove(), lingerMs);
  }

  /** Takes away the messages of `topic` (what they said no longer holds). */
  dismiss(topic: string): void {
    for (const old of this.root.querySelectorAll<HTMLElement>('.message[data-topic]')) {
      if (old.dataset.topic === topic) old.remove();
    }
  }
}
