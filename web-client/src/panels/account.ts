// The header's account line: who is signed in and what they use of their
// quotas ("alice — 12.0 MiB of 500 MiB · 1 of 4 jobs"), and "Sign out",
// which forgets the stored token and starts again (the server then asks for
// one).  A loopback server's local user has no token: no button then.
import { getToken, setToken } from '../api/auth.ts';
import type { Me } from '../api/types.ts';
import { el, formatBytes } from './dom.ts';

export function usageText(me: Me): string {
  const storage =
    me.storage_bytes_limit === null ? `${formatBytes(me.storage_bytes_used)} stored` : `${formatBytes(me.storage_bytes_used)} of ${formatBytes(me.storage_bytes_limit)}`;
  const jobs = me.jobs_limit === null ? '' : ` · ${me.jobs_active} of ${me.jobs_limit} jobs`;
  return `${me.user} — ${storage}${jobs}`;
}

export class AccountPanel {
  private readonly root: HTMLElement;
  private readonly signOut: HTMLButtonElement;
  private readonly text: HTMLElement;

  constructor(root: HTMLElement, onSignOut: () => void = () => location.reload()) {
    this.root = root;
    this.text = el('span', { class: 'account-usage' });
    this.signOut = el('button', { type: 'button', class: 'button small sign-out', title: 'Forget the token on this browser' }, 'Sign out');
    this.signOut.addEventListener('click', () => {
      setToken(null);
      onSignOut();
    });
    this.root.replaceChildren(this.text, this.signOut);
    this.root.hidden = true;
  }

  render(me: Me): void {
    this.root.hidden = false;
    this.root.dataset.user = me.user;
    this.text.textContent = usageText(me);
    const over = me.storage_bytes_limit !== null && me.storage_bytes_used >= me.storage_bytes_limit;
    this.text.classList.toggle('over', over);
    // The line is cut with an ellipsis when the toolbar is short of room: its title keeps the whole of it.
    this.text.title = over ? `${this.text.textContent} — storage quota reached: delete meshes to upload more` : this.text.textContent;
    this.signOut.hidden = !getToken();
  }
}
