// Bearer tokens (protocol/API.md "Users and tokens").  A server on loopback
// needs none, and nothing here changes a request then; where the server
// answers 401, the viewer asks once for a token (tokenForm), keeps it in
// localStorage, and sends it as the Authorization header on every fetch and
// as the WebSocket's first message.  Tokens never go into URLs (they would
// be logged): thumbnails and downloads are fetched, then shown from blob URLs.

import { clearSession, pastedTicket, sessionToken } from './tickets.ts';

const KEY = 'cgview.token';

/** The credential requests carry: this tab's session from a sign-in ticket (api/tickets.ts), else the stored token. */
export function getToken(): string | null {
  const session = sessionToken();
  if (session) return session;
  try {
    return localStorage.getItem(KEY);
  } catch {
    return null; // storage disabled
  }
}

export function setToken(token: string | null): void {
  clearSession(); // a token typed, refused or forgotten ends a ticket's session too
  if (token) localStorage.setItem(KEY, token);
  else localStorage.removeItem(KEY);
}

type Handler = () => void;
const unauthorizedHandlers = new Set<Handler>();

/** Called when the server refuses the request for its token (401, or the WebSocket's `unauthorized`). */
export function onUnauthorized(handler: Handler): () => void {
  unauthorizedHandlers.add(handler);
  return () => unauthorizedHandlers.delete(handler);
}

export function reportUnauthorized(): void {
  for (const h of unauthorizedHandlers) h();
}

/** fetch with the stored token, if any, as `Authorization: Bearer`. */
export async function authFetch(url: string, init: RequestInit = {}): Promise<Response> {
  const token = getToken();
  if (token) {
    const headers = new Headers(init.headers);
    headers.set('Authorization', `Bearer ${token}`);
    init = { ...init, headers };
  }
  const response = await fetch(url, init);
  if (response.status === 401) reportUnauthorized();
  return response;
}

/** Shows `url` in an image: as it is without a token, else fetched with it into a blob URL. */
export function setImageSource(img: HTMLImageElement, url: string): void {
  if (!getToken()) {
    img.src = url;
    return;
  }
  // Until the blob arrives the image has no src, so `complete` says true: `fetching` tells it is on its way.
  img.dataset.fetching = '';
  authFetch(url)
    .then(async (r) => {
      if (!r.ok) throw new Error(`HTTP ${r.status}`);
      const blobUrl = URL.createObjectURL(await r.blob());
      img.addEventListener('load', () => URL.revokeObjectURL(blobUrl), { once: true });
      img.src = blobUrl;
    })
    .catch(() => img.dispatchEvent(new Event('error')))
    .finally(() => delete img.dataset.fetching);
}

/**
 * With a token, a click on a download link to the API fetches the file with
 * the token and saves it from a blob URL (a plain link would get 401).
 */
export function installAuthorizedDownloads(root: Document = document): void {
  root.addEventListener('click', (ev) => {
    const a = (ev.target as Element | null)?.closest?.('a[download]') as HTMLAnchorElement | null;
    if (!a || !getToken() || !a.getAttribute('href')?.startsWith('/api/')) return;
    ev.preventDefault();
    void authFetch(a.href).then(async (r) => {
      if (!r.ok) return;
      const name = /filename="([^"]+)"/.exec(r.headers.get('Content-Disposition') ?? '')?.[1] ?? 'download';
      saveBlob(await r.blob(), name, root);
    });
  });
}

let asking: Promise<void> | null = null;

/**
 * The sign-in box, written for a student: paste the sign-in link the teacher
 * sent (or a token); `note` first says what went wrong (a link used already).
 * Asks once, however many requests were refused; resolves when a token is
 * stored, or a pasted link's ticket put in the address for the reload to
 * redeem (api/tickets.ts).
 */
export function tokenForm(note: string | null = null): Promise<void> {
  asking ??= new Promise((resolve) => {
    setToken(null); // the stored one, if any, was refused
    const make = <K extends keyof HTMLElementTagNameMap>(tag: K, props: Partial<HTMLElementTagNameMap[K]> = {}): HTMLElementTagNameMap[K] =>
      Object.assign(document.createElement(tag), props);
    const form = make('form', { id: 'token-form', className: 'token-form' });
    form.setAttribute('aria-labelledby', 'token-form-title');
    const title = make('h2', { id: 'token-form-title', textContent: 'Sign in to CGView' });
    const intro = make('p', { textContent: 'Open the sign-in link your teacher sent you, or paste it here.' });
    const label = make('label', { textContent: 'Sign-in link or token' });
    const input = make('input', { type: 'password', name: 'token', autocomplete: 'off', spellcheck: false });
    const button = make('button', { type: 'submit', className: 'button', textContent: 'Sign in' });
    const hint = make('p', { className: 'token-form-hint', textContent: 'No link, or it no longer works? Ask your teacher for a new one: each link works once.' });
    label.append(input);
    form.append(title);
    if (note) form.append(make('p', { className: 'token-form-note', textContent: note }));
    form.append(intro, label, button, hint);
    form.addEventListener('submit', (ev) => {
      ev.preventDefault();
      const text = input.value.trim();
      if (!text) return;
      const ticket = pastedTicket(text);
      if (ticket) history.replaceState(history.state, '', `${location.pathname}${location.search}#ticket=${encodeURIComponent(ticket)}`);
      else setToken(text);
      form.remove();
      document.body.classList.remove('signing-in');
      resolve();
    });
    document.body.append(form);
    document.body.classList.add('signing-in');
    input.focus();
  });
  return asking;
}

/** Saves `blob` as a file named `name` (the browser's download), its blob URL let go once the download has it. */
export function saveBlob(blob: Blob, name: string, root: Document = document): void {
  const url = URL.createObjectURL(blob);
  const link = Object.assign(root.createElement('a'), { href: url, download: name });
  root.body.append(link);
  link.click();
  link.remove();
  setTimeout(() => URL.revokeObjectURL(url), 10_000);
}
