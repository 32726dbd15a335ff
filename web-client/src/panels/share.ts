// "Share…" on a mesh, a job or a plugin: a small form that shares it with users (by
// name, comma-separated) and/or everyone, or takes that back, with the
// server's routes (POST …/share, …/unshare); it shows who reads it now, or
// the server's reason for refusing (403: not the owner; 400: no such user).
import { setSharing } from '../api/rest.ts';
import type { Sharing } from '../api/types.ts';
import { el } from './dom.ts';

function describeSharing(s: Sharing): string {
  const who = [...s.users.filter((u) => u !== '*'), ...(s.everyone ? ['everyone'] : [])];
  return who.length ? `Shared with ${who.join(', ')}.` : 'Not shared.';
}

/** Opens the form for one item (one at a time: a second call replaces the first). */
export function openShareForm(kind: 'meshes' | 'jobs' | 'plugins', id: string, title: string): HTMLFormElement {
  document.getElementById('share-form')?.remove();
  const users = el('input', { type: 'text', name: 'users', placeholder: 'user names, comma-separated', autocomplete: 'off' });
  const everyone = el('input', { type: 'checkbox', name: 'everyone' });
  const status = el('p', { class: 'share-status', role: 'status' });
  const share = el('button', { type: 'submit', class: 'button share-submit' }, 'Share');
  const unshare = el('button', { type: 'button', class: 'button unshare-submit' }, 'Unshare');
  const close = el('button', { type: 'button', class: 'button share-close' }, 'Close');
  const form = el(
    'form',
    { id: 'share-form', class: 'share-form', 'data-kind': kind, 'data-id': id },
    el('h3', {}, `Share ${title}`),
    el('label', {}, 'With ', users),
    el('label', { class: 'share-everyone' }, everyone, ' everyone'),
    el('div', { class: 'share-buttons' }, share, unshare, close),
    status,
  );
  const send = async (add: boolean) => {
    const names = users.value.split(/[\s,]+/).filter(Boolean);
    if (!names.length && !everyone.checked) {
      status.textContent = 'Name a user or tick everyone.';
      status.className = 'share-status form-error';
      return;
    }
    share.disabled = unshare.disabled = true;
    try {
      const result = await setSharing(kind, id, { users: names, everyone: everyone.checked }, add);
      status.textContent = describeSharing(result);
      status.className = 'share-status';
      form.dataset.done = String(Date.now());
    } catch (e) {
      status.textContent = (e as Error).message;
      status.className = 'share-status form-error';
    } finally {
      share.disabled = unshare.disabled = false;
    }
  };
  form.addEventListener('submit', (ev) => {
    ev.preventDefault();
    void send(true);
  });
  unshare.addEventListener('click', () => void send(false));
  close.addEventListener('click', () => form.remove());
  document.body.append(form);
  users.focus();
  return form;
}
