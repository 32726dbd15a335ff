import './styles.css';
import { installAuthorizedDownloads, onUnauthorized, tokenForm } from './api/auth.ts';
import { App } from './app.ts';

// A server that needs a token (protocol/API.md "Users and tokens"): ask once,
// keep it, and start again with it.  On loopback this never happens.
installAuthorizedDownloads();
onUnauthorized(() => {
  void tokenForm('This server needs a token (cgview-server user add NAME prints one):').then(() => location.reload());
});

const app = new App();
void app.start();
