import './styles.css';
import { getToken, installAuthorizedDownloads, onUnauthorized, setToken, tokenForm } from './api/auth.ts';
import { redeemTicket, tellParent } from './api/tickets.ts';
import { App } from './app.ts';

/** Why the token form asks: a course's sign-in link refused says so. */
let asking = 'This server needs a token (cgview-server user add NAME prints one):';

// A server that needs a token (protocol/API.md "Users and tokens"): ask once,
// keep it, and start again with it.  On loopback this never happens.
installAuthorizedDownloads();
onUnauthorized(() => {
  void tokenForm(asking).then(() => location.reload());
});

// A page opened with a sign-in ticket (a notebook's view, or a course's
// one-time link: api/tickets.ts) signs in with it before anything asks the
// server. A course's link opens the Course panel.
void redeemTicket(setToken).then((outcome) => {
  void tellParent(getToken());
  const refusedLink = outcome === 'refused-link';
  if (refusedLink) asking = 'This sign-in link is used or expired: ask your teacher for another, or sign in with a token:';
  const app = new App({ openCourse: outcome === 'token', refusedLink });
  void app.start();
});
