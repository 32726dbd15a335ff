// Messages shown in the page: errors stay until dismissed, notices fade.
import { el } from './dom.ts';

const MAX_SHOWN = 5;

export class MessagesPanel {
  private readonly root: HTMLElement;

  constructor(root: HTMLElement) {
    this.root = root;
  }

  error(text: string): void {
    this.add('error', text, 0);
  }

  notice(text: string): void {
    this.add('notice', text, 4000);
  }

  private add(kind: 'error' | 'notice', text: string, timeoutMs: number): void {
    const close = el('button', { type: 'button', class: 'close', 'aria-label': 'Dismiss' }, '✕');
    const item = el('div', { class: `message ${kind}`, role: kind === 'error' ? 'alert' : 'status' }, el('span', { class: 'text' }, text), close);
    close.addEventListener('click', () => item.remove());
    this.root.append(item);
    while (this.root.children.length > MAX_SHOWN) this.root.firstElementChild!.remove();
    if (timeoutMs > 0) setTimeout(() => item.remove(), timeoutMs);
  }
}
