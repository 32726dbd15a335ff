"""A text progress bar for jobs, on a terminal or in a log."""
import sys

from .client import TERMINAL_STATES


class ProgressBar:
    """Call with each job state: on a terminal one line redrawn in place,
    elsewhere a line each time the stage changes or 10% more is done."""

    def __init__(self, stream=None, width=30):
        self.stream = stream or sys.stderr
        self.width = width
        self.tty = self.stream.isatty()
        self.last = None

    def __call__(self, job):
        fraction = min(max(float(job.get("progress") or 0.0), 0.0), 1.0)
        if job["state"] == "done":
            fraction = 1.0
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
