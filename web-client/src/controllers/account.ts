// The signed-in user and their quota use (GET /me), shown in the header and
// asked for again soon after anything that may change them.
import { getMe } from '../api/rest.ts';
import { AccountPanel } from '../panels/account.ts';
import type { AppStore } from '../state/app_state.ts';

export class AccountController {
  private readonly store: AppStore;
  private timer: ReturnType<typeof setTimeout> | null = null;

  constructor(store: AppStore, panel: AccountPanel) {
    this.store = store;
    store.subscribe(
      (s) => s.me,
      (me) => {
        if (me) panel.render(me);
      },
    );
  }

  async refresh(): Promise<void> {
    try {
      this.store.update({ me: await getMe() });
    } catch {
      // An older server without /me: no account line.
    }
  }

  /** Asks the server again who the user is and what they use (soon after a change, once for a burst of them). */
  refreshSoon(): void {
    if (this.timer) return;
    this.timer = setTimeout(() => {
      this.timer = null;
      void this.refresh();
    }, 300);
  }

  /** An item's owner when it is another user (a student's work shared with their teacher), to name beside it; null for the user's own and the samples. */
  otherOwner(owner: string | undefined): string | null {
    const me = this.store.get().me;
    return me && owner && owner !== me.user && owner !== 'system' ? owner : null;
  }

  /** Whether the user may share or delete an item of that owner (the server decides in the end). */
  mayChange(owner: string | undefined): boolean {
    const me = this.store.get().me;
    return !me || me.admin || owner === undefined || owner === me.user;
  }
}
