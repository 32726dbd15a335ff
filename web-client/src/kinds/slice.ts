// A kind's part of the application state: what the job list shows of its
// artifacts (the skeletons drawn and their colours, the metrics fetched...),
// kept under the kind's string in `AppState.artifacts`, so that the state, the
// job list and the jobs controller need not name any kind. The kind's module
// writes its part; its row reads it back from the state the list is built from.
import type { AppState, AppStore } from '../state/app_state.ts';

export class KindSlice<T> {
  constructor(
    readonly kind: string,
    private readonly empty: T,
  ) {}

  /** The kind's part of `state` (its empty value until the kind writes one). */
  get(state: Readonly<AppState>): T {
    return (state.artifacts[this.kind] as T | undefined) ?? this.empty;
  }

  /** Replaces the kind's part: with `value`, or with what `change` makes of the part as it is. */
  set(store: AppStore, value: T | ((now: T) => T)): void {
    store.update((s) => ({
      artifacts: { ...s.artifacts, [this.kind]: typeof value === 'function' ? (value as (now: T) => T)(this.get(s)) : value },
    }));
  }
}
