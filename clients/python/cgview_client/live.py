"""Live job events over the server's WebSocket (/api/v1/ws), with Debian's
python3-websocket when it is installed; without it the client polls."""
import json
import socket

try:
    import websocket  # python3-websocket (websocket-client)
except ImportError:
    websocket = None


def ws_url(url):
    """The WebSocket address of a server at http(s)://HOST:PORT."""
    scheme, rest = url.split("://", 1)
    return ("wss" if scheme == "https" else "ws") + "://" + rest + "/api/v1/ws"


def authenticate(ws, token):
    """Presents the token on an open connection.  The handshake already
    carries it as a header; the first message is for servers that read it
    there (as browsers, which cannot set headers, need)."""
    ws.send(json.dumps({"type": "auth", "token": token}))


class JobEvents:
    """The job events of one connection: job_progress, job_done, job_failed, job_cancelled."""

    def __init__(self, url, token=None, ca_file=None):
        self.url, self.token, self.ca_file, self.ws = url, token, ca_file, None

    def open(self):
        """Connects; False when it cannot (no python3-websocket, no WebSocket there)."""
        if websocket is None:
            return False
        headers = [f"Authorization: Bearer {self.token}"] if self.token else []
        try:
            sslopt = {"ca_certs": self.ca_file} if self.ca_file else None
            self.ws = websocket.create_connection(ws_url(self.url), timeout=10, header=headers, sslopt=sslopt)
            if self.token:
                authenticate(self.ws, self.token)
        except (OSError, websocket.WebSocketException):
            self.ws = None
        return self.ws is not None

    @property
    def connected(self):
        return self.ws is not None

    def next_for(self, job_id, timeout):
        """The job object of the next event about job_id, or None when none
        came within about timeout seconds (or the connection closed)."""
        if self.ws is None:
            return None
        self.ws.settimeout(timeout)
        while True:
            try:
                message = self.ws.recv()
            except (socket.timeout, websocket.WebSocketTimeoutException):
                return None
            except (OSError, websocket.WebSocketException):
                self.close()
                return None
            if not isinstance(message, str):
                continue  # binary payloads are for other requests
            event = json.loads(message)
            job = event.get("job")
            if event.get("type", "").startswith("job_") and isinstance(job, dict) and job.get("id") == job_id:
                return job

    def close(self):
        if self.ws is not None:
            self.ws.close()
            self.ws = None
