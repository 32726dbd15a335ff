"""Progress bars for jobs: text on a terminal or in a log, HTML in a notebook."""
import html
import sys

from .client import TERMINAL_STATES


def _fraction(job):
    fraction = min(max(float(job.get("progress") or 0.0), 0.0), 1.0)
    return 1.0 if job["state"] == "done" else fraction


class ProgressBar:
    """Call with each job state: on a terminal one line redrawn in place,
    elsewhere a line each time the stage changes or 10% more is done."""

    def __init__(self, stream=None, width=30):
        self.stream = stream or sys.stderr
        self.width = width
        self.tty = self.stream.isatty()
        self.last = None

    def __call__(self, job):
        fraction = _fraction(job)
        stage = job.get("stage") or job["state"]
        key = (job["state"], stage, int(fraction * 10))
        if not self.tty and key == self.last:
            return
        self.last = key
        filled = round(fraction * self.width)
        line = f"{job.get('algorithm', job['id'])} [{'#' * filled}{'.' * (self.width - filled)}] {fraction:4.0%} {stage}"
        end = "\n" if not self.tty or job["state"] in TERMINAL_STATES else ""
        self.stream.write(("\r\033[K" if self.tty else "") + line + end)
        self.stream.flush()


def in_notebook():
    """True inside an IPython kernel (Jupyter, nbclient, VS Code), where
    output cells show HTML; False in a script or a terminal IPython."""
    # A kernel has imported IPython long before any of this runs: a script
    # that has not must not pay for importing it here.
    if "IPython" not in sys.modules:
        return False
    get_ipython = getattr(sys.modules["IPython"], "get_ipython", None)
    shell = get_ipython() if get_ipython else None
    return shell is not None and getattr(shell, "kernel", None) is not None


class NotebookProgressBar:
    """Call with each job state: one HTML bar in the output cell, updated in
    place (IPython's display(..., display_id=True)); no widgets needed.
    Several jobs share one bar with total=N: call next() before each job after
    the first, and the bar shows the whole's share done and the job's place."""

    def __init__(self, total=1, width="24em"):
        self.total = max(int(total), 1)
        self.index = 0
        self.width = width
        self.handle = None
        self.last = None

    def next(self):
        self.index = min(self.index + 1, self.total - 1)

    def bundle(self, job):
        """The text/html and text/plain of a job's state (text/plain for a
        front end without HTML, and for saved notebooks read as text)."""
        fraction = (self.index + _fraction(job)) / self.total
        stage = job.get("stage") or job["state"]
        name = job.get("algorithm", job["id"])
        if self.total > 1:
            name = f"{name} {self.index + 1}/{self.total}"
        colour = {"done": "#2e7d32", "failed": "#c62828", "cancelled": "#757575", "interrupted": "#757575"}.get(
            job["state"], "#1565c0")
        percent = f"{fraction:.0%}"
        page = (f'<div class="cgview-progress" style="font-family:monospace">'
                f'{html.escape(name)} '
                f'<span style="display:inline-block;width:{self.width};height:0.9em;border:1px solid #999;'
                f'vertical-align:middle;background:#eee">'
                f'<span style="display:block;height:100%;width:{fraction * 100:.1f}%;background:{colour}"></span>'
                f'</span> {percent} {html.escape(stage)}</div>')
        return {"text/html": page, "text/plain": f"{name} {percent} {stage}"}

    def __call__(self, job):
        from IPython.display import display
        bundle = self.bundle(job)
        if bundle == self.last:
            return  # the same picture: no message to the front end
        self.last = bundle
        if self.handle is None:
            self.handle = display(bundle, raw=True, display_id=True)
        else:
            self.handle.update(bundle, raw=True)


def default_progress(on_progress, total=1):
    """What waiting shows when the caller gave no on_progress: an HTML bar in
    a notebook, nothing elsewhere (a script's output stays its own).  False
    turns the notebook's bar off too."""
    if on_progress is False:
        return None
    if on_progress is None and in_notebook():
        return NotebookProgressBar(total)
    return on_progress
