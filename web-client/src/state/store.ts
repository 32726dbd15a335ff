// One application state and those who read it: a panel subscribes with a
// selector (the part it shows) and is called right after an update that
// changes that part, never for an update that leaves it as it was. Imports
// nothing, so that node's unit tests load it as it is.

export type Selector<S, T> = (state: Readonly<S>) => T;
export type Equality<T> = (a: T, b: T) => boolean;

function isPlainObject(v: unknown): v is Record<string, unknown> {
  return typeof v === 'object' && v !== null && Object.getPrototypeOf(v) === Object.prototype;
}

/**
 * Equal one level deep: the same items in the same order (arrays), the same
 * keys with the same values (plain objects), or the same value (Object.is).
 * Maps, sets and other objects are compared by identity: an update replaces
 * them when they change.
 */
export function shallowEqual(a: unknown, b: unknown): boolean {
  if (Object.is(a, b)) return true;
  if (Array.isArray(a) && Array.isArray(b)) return a.length === b.length && a.every((v, i) => Object.is(v, b[i]));
  if (isPlainObject(a) && isPlainObject(b)) {
    const keys = Object.keys(a);
    return keys.length === Object.keys(b).length && keys.every((k) => Object.prototype.hasOwnProperty.call(b, k) && Object.is(a[k], b[k]));
  }
  return false;
}

interface Subscription<S> {
  select: Selector<S, unknown>;
  listener: (value: unknown, previous: unknown) => void;
  equals: Equality<unknown>;
  last: unknown;
}

export interface SubscribeOptions<T> {
  /** When the selected part counts as unchanged (default: shallowEqual). */
  equals?: Equality<T>;
  /** Also calls the listener now, with the part as it is. */
  now?: boolean;
}

export class Store<S extends object> {
  private state: S;
  private readonly subscriptions = new Set<Subscription<S>>();

  constructor(initial: S) {
    this.state = initial;
  }

  get(): Readonly<S> {
    return this.state;
  }

  /**
   * Replaces the fields given (a partial state, or a function of the state
   * now that returns one), then calls the subscribers whose part changed. A
   * subscriber that updates in turn is served first; those after it compare
   * with the latest state, so each sees every change once.
   */
  update(change: Partial<S> | ((state: Readonly<S>) => Partial<S>)): void {
    const patch = typeof change === 'function' ? change(this.state) : change;
    this.state = { ...this.state, ...patch };
    for (const s of [...this.subscriptions]) {
      if (!this.subscriptions.has(s)) continue; // unsubscribed by an earlier listener
      const value = s.select(this.state);
      if (s.equals(s.last, value)) continue;
      const previous = s.last;
      s.last = value;
      s.listener(value, previous);
    }
  }

  /** Calls `listener` whenever `select(state)` changes. Returns a function that unsubscribes. */
  subscribe<T>(select: Selector<S, T>, listener: (value: T, previous: T) => void, options: SubscribeOptions<T> = {}): () => void {
    const s: Subscription<S> = {
      select,
      listener: listener as Subscription<S>['listener'],
      equals: (options.equals ?? shallowEqual) as Equality<unknown>,
      last: select(this.state),
    };
    this.subscriptions.add(s);
    if (options.now) listener(s.last as T, s.last as T);
    return () => {
      this.subscriptions.delete(s);
    };
  }
}
