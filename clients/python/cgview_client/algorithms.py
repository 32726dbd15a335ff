"""The server's algorithms as methods: client.algorithms.sdf(mesh, rays=25)
runs a job and waits for it; help(client.algorithms.sdf) shows each
parameter's range and meaning.  Calling client.algorithms() lists them as
the server describes them."""
from . import params


class Algorithms:
    def __init__(self, client):
        self._client = client
        self._list = None

    def __call__(self):
        """The algorithms as GET /api/v1/algorithms lists them."""
        return self._client.get_json("/algorithms")["algorithms"]

    def _by_name(self):
        if self._list is None:
            self._list = {a["name"]: a for a in self()}
        return self._list

    def describe(self, name):
        """The algorithm's entry; LookupError naming the closest one."""
        known = self._by_name()
        if name not in known:
            import difflib
            close = difflib.get_close_matches(name, list(known), n=1)
            raise LookupError(f"the server has no algorithm '{name}'" + (f" (did you mean '{close[0]}'?)" if close else ""))
        return known[name]

    def __getattr__(self, name):
        if name.startswith("_"):
            raise AttributeError(name)
        try:
            algorithm = self.describe(name)
        except LookupError as e:
            raise AttributeError(str(e)) from None
        client = self._client

        def run(mesh, *, inputs=None, on_progress=None, timeout=None, **parameters):
            return client.run(name, mesh, inputs=inputs, on_progress=on_progress, timeout=timeout, **parameters)

        run.__name__ = name
        run.__qualname__ = f"Algorithms.{name}"
        run.__doc__ = params.describe(algorithm) + "\n\nRuns the job on `mesh` (a Mesh or an id) and waits; the done Job."
        return run

    def __dir__(self):
        return sorted(set(super().__dir__()) | set(self._by_name()))
