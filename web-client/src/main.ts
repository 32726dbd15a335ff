import './styles.css';
import { getToken, installAuthorizedDownloads, onUnauthorized, tokenForm } from './api/auth.ts';
import { redeemTicket, tellParent } from './api/tickets.ts';
import { App } from './app.ts';

// A server that needs a token (protocol/API.md "Users and tokens"): ask once,
// keep it, and start again with it.  On loopback this never happens.
installAuthorizedDownloads();
onUnauthorized(() => {
  void tokenForm('This server needs a token (cgview-server user add NAME prints one):').then(() => location.reload());
});

// A page opened with a sign-in ticket (a notebook's view, api/tickets.ts)
// signs in with it before anything asks the server.
void redeemTicket().then(() => {
  void tellParent(getToken());
  const app = new App();
  void app.start();
});
