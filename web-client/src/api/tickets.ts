// Sign-in tickets (protocol/API.md "Users and tokens"): the viewer opened in
// a notebook's output cell (clients/python's show()) gets a ticket, good
// once and for a minute, in its address's hash (`#view=…&ticket=cgt_…`; no
// browser sends a hash to a server), never a token. It takes the ticket out
// of the address at once and redeems it for a session of the ticket's user,
// kept for this tab alone (sessionStorage, not the token's localStorage,
// which a signed-in viewer of another user on the same site may share) until
// it expires: api/auth.ts sends it as it sends a token. In a frame, the page
// then tells the page around it whether it can show the view, so that the
// output shows the viewer or, failing that, keeps its picture.
//
// A course's one-time sign-in link (`#ticket=cgl_…`, mailed to a student by
// their teacher) is redeemed the same way, but for a token of the student's
// own (`"kind":"token"`): the page keeps it as it keeps a token typed in
// (api/auth.ts, localStorage), not as a session of this tab.

const SESSION_KEY = 'cgview.session';

interface StoredSession {
  token: string;
  /** When it ends, in ms since the epoch. */
  expires: number;
}

/** This tab's session from a ticket, while it lasts; null when none. */
export function sessionToken(): string | null {
  try {
    const raw = sessionStorage.getItem(SESSION_KEY);
    if (!raw) return null;
    const s = JSON.parse(raw) as Partial<StoredSession> | null;
    if (typeof s?.token === 'string' && typeof s.expires === 'number' && s.expires > Date.now()) return s.token;
    sessionStorage.removeItem(SESSION_KEY);
  } catch {
    // storage disabled, or not our JSON: no session
  }
  return null;
}

/** Ends this tab's session (a token typed, refused or forgotten). */
export function clearSession(): void {
  try {
    sessionStorage.removeItem(SESSION_KEY);
  } catch {
    // storage disabled: nothing kept
  }
}

/**
 * What the page's ticket came to: none given, a session, a token of the
 * user's own (a course's sign-in link), or refused (used, expired, forged;
 * `refused-link`: a course's sign-in link).
 */
export type TicketOutcome = 'none' | 'signed-in' | 'token' | 'refused' | 'refused-link';

/** A course's sign-in link, as opposed to a notebook's ticket. */
export const COURSE_LINK_PREFIX = 'cgl_';

/** The course sign-in ticket (`cgl_…`) in what was pasted: a whole sign-in link, or the ticket alone; null for anything else (a token). */
export function pastedTicket(text: string): string | null {
  const m = /(?:^|[#&?]ticket=)(cgl_[A-Za-z0-9_-]+)(?:$|&)/.exec(text.trim());
  return m ? m[1]! : null;
}

/**
 * Redeems the ticket of the page's hash, if it has one, after taking it out
 * of the address (a reload or a copied link must not carry it). A refused
 * ticket leaves an earlier session of this tab in place: the same output
 * cell's frame, drawn again, finds it. A course's link gives a token, handed
 * to `keepToken`.
 */
export async function redeemTicket(keepToken: (token: string) => void): Promise<TicketOutcome> {
  const params = new URLSearchParams(location.hash.slice(1));
  const ticket = params.get('ticket');
  if (ticket === null) return 'none';
  params.delete('ticket');
  const rest = params.toString();
  history.replaceState(history.state, '', `${location.pathname}${location.search}${rest ? `#${rest}` : ''}`);
  const link = ticket.startsWith(COURSE_LINK_PREFIX);
  const refused: TicketOutcome = link ? 'refused-link' : 'refused';
  try {
    const r = await fetch('/api/v1/tickets/redeem', {
      method: 'POST',
      headers: { 'Content-Type': 'application/json' },
      body: JSON.stringify({ ticket }),
    });
    if (!r.ok) return refused;
    const s = (await r.json()) as { token?: unknown; expires_s?: unknown; kind?: unknown };
    if (link || s.kind === 'token') {
      if (typeof s.token !== 'string') return refused;
      keepToken(s.token);
      return 'token';
    }
    if (typeof s.token !== 'string' || typeof s.expires_s !== 'number') return refused;
    const stored: StoredSession = { token: s.token, expires: Date.now() + s.expires_s * 1000 };
    sessionStorage.setItem(SESSION_KEY, JSON.stringify(stored));
    return 'signed-in';
  } catch {
    return refused;
  }
}

/**
 * In a frame, tells the page around it (a notebook's output) whether this
 * one can show the view: the server answers it, with `token` or without one.
 * The message holds nothing but that.
 */
export async function tellParent(token: string | null): Promise<void> {
  if (window.parent === window) return;
  let ready = false;
  try {
    const r = await fetch('/api/v1/me', { headers: token ? { Authorization: `Bearer ${token}` } : {} });
    ready = r.ok;
  } catch {
    // the server is gone: not ready
  }
  window.parent.postMessage({ type: 'cgview-embed', ready }, '*');
}
