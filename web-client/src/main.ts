import './styles.css';
import { getToken, installAuthorizedDownloads, onUnauthorized, setToken, tokenForm } from './api/auth.ts';
import { redeemTicket, tellParent } from './api/tickets.ts';
import { App } from './app.ts';

/** What the sign-in box says first: why a course's sign-in link was refused; nothing otherwise. */
let note: string | null = null;

// A server that needs a token (protocol/API.md "Users and tokens"): ask once,
// keep it, and start again with it.  On loopback this never happens.
installAuthorizedDownloads();
onUnauthorized(() => {
  void tokenForm(note).then(() => location.reload());
});

// A page opened with a sign-in ticket (a notebook's view, or a course's
// one-time link: api/tickets.ts) signs in with it before anything asks the
// server. A course's link opens the Course panel.
void redeemTicket(setToken).then((outcome) => {
  void tellParent(getToken());
  const refusedLink = outcome === 'refused-link';
  if (refusedLink) note = 'This sign-in link is used or expired: ask your teacher for another.';
  const app = new App({ openCourse: outcome === 'token', refusedLink });
  void app.start();
});
