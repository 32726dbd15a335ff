// Undo for what destroys: deleting a mesh, clearing a selection, leaving a
// comparison. What was done shows at once (the mesh leaves the list, the
// selection empties) with a notice that offers "Undo" for a few seconds;
// what cannot be taken back (the DELETE request) is sent only when that time
// is up, or when the page goes away. Undo puts things back as they were.
import type { AppStore } from '../state/app_state.ts';
import type { TestHooks } from '../test_hooks.ts';

/** How long "Undo" is offered. */
export const UNDO_MS = 6000;

export interface UndoActions {
  /** Puts back what was done (called at most once, and only before commit). */
  undo: () => void;
  /** Does what cannot be taken back, once the offer ends without an undo (none: nothing to do). */
  commit?: () => void;
}

interface Offer {
  commit: () => void;
  timer: number;
}

export class UndoOffers {
  private readonly pending = new Set<Offer>();

  constructor(
    private readonly store: AppStore,
    private readonly hooks: TestHooks,
  ) {
    // The page going away ends every offer: what was done stays done.
    window.addEventListener('pagehide', () => this.commitAll());
  }

  /** Shows `text` with an "Undo" button for UNDO_MS: undo() if it is pressed in time, commit() once the time is up. */
  offer(text: string, actions: UndoActions): void {
    const offer: Offer = { commit: actions.commit ?? (() => {}), timer: 0 };
    offer.timer = window.setTimeout(() => this.end(offer, true), UNDO_MS);
    this.pending.add(offer);
    this.report();
    this.store.update({
      message: {
        level: 'notice',
        text,
        timeoutMs: UNDO_MS,
        action: {
          label: 'Undo',
          run: () => {
            if (this.end(offer, false)) actions.undo();
          },
        },
      },
    });
  }

  /** Ends every offer now, doing what each one held back. */
  commitAll(): void {
    for (const offer of [...this.pending]) this.end(offer, true);
  }

  /** Ends an offer (committing it, or not: undone); false when it had ended already. */
  private end(offer: Offer, commit: boolean): boolean {
    if (!this.pending.delete(offer)) return false;
    window.clearTimeout(offer.timer);
    this.report();
    if (commit) offer.commit();
    return true;
  }

  private report(): void {
    this.hooks.pendingUndo = this.pending.size;
  }
}
