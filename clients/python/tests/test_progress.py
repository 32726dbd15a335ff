"""cgview_client.ProgressBar: a line per stage or 10% in a log, one redrawn line on a terminal;
NotebookProgressBar: one HTML bar in a notebook."""
import io
import sys
import types
import unittest
from unittest import mock

from cgview_client import ProgressBar
from cgview_client.progress import NotebookProgressBar, default_progress, in_notebook


class Terminal(io.StringIO):
    def isatty(self):
        return True


def job(state, progress, stage):
    return {"id": "j1", "algorithm": "sdf", "state": state, "progress": progress, "stage": stage}


class ProgressBarTest(unittest.TestCase):
    def test_log_gets_a_line_per_change(self):
        out = io.StringIO()
        bar = ProgressBar(out, width=10)
        for j in [job("queued", 0, ""), job("running", 0.31, "rays"), job("running", 0.33, "rays"),
                  job("running", 0.45, "rays"), job("done", 0.9, "done")]:
            bar(j)
        self.assertEqual(out.getvalue().split("\n"), [
            "sdf [..........]   0% queued",
            "sdf [###.......]  31% rays",
            "sdf [####......]  45% rays",
            "sdf [##########] 100% done",
            "",
        ])

    def test_terminal_redraws_one_line(self):
        out = Terminal()
        bar = ProgressBar(out, width=4)
        bar(job("running", 0.5, "rays"))
        bar(job("failed", 0.5, "rays"))
        self.assertEqual(out.getvalue(), "\r\033[Ksdf [##..]  50% rays\r\033[Ksdf [##..]  50% rays\n")


class NotebookProgressBarTest(unittest.TestCase):
    """The HTML bar's pictures, and when waiting shows it; the bar in a real
    kernel is test_notebooks.py's."""

    def test_bundle_shows_the_share_done_and_the_stage(self):
        bar = NotebookProgressBar()
        done = bar.bundle(job("done", 0.9, "done"))
        self.assertEqual(done["text/plain"], "sdf 100% done")
        self.assertIn("width:100.0%", done["text/html"])
        self.assertIn('class="cgview-progress"', done["text/html"])
        running = bar.bundle(job("running", 0.25, "<rays>"))
        self.assertEqual(running["text/plain"], "sdf 25% <rays>")
        self.assertIn("25% &lt;rays&gt;", running["text/html"])

    def test_several_jobs_share_one_bar(self):
        bar = NotebookProgressBar(total=3)
        self.assertEqual(bar.bundle(job("done", 1, "done"))["text/plain"], "sdf 1/3 33% done")
        bar.next()
        self.assertEqual(bar.bundle(job("running", 0.5, "rays"))["text/plain"], "sdf 2/3 50% rays")
        bar.next()
        bar.next()  # never past the last
        self.assertEqual(bar.bundle(job("done", 1, "done"))["text/plain"], "sdf 3/3 100% done")

    def test_outside_a_kernel_nothing_is_shown_unless_asked(self):
        with mock.patch.dict(sys.modules):  # a script that never imported IPython
            sys.modules.pop("IPython", None)
            self.assertFalse(in_notebook())
            self.assertIsNone(default_progress(None))
        bar = ProgressBar(io.StringIO())
        self.assertIs(default_progress(bar), bar)
        self.assertIsNone(default_progress(False))

    def test_in_a_kernel_waiting_shows_the_html_bar(self):
        kernel = types.SimpleNamespace(kernel=object())
        with mock.patch.dict(sys.modules, {"IPython": types.SimpleNamespace(get_ipython=lambda: kernel)}):
            self.assertTrue(in_notebook())
            self.assertIsInstance(default_progress(None, total=2), NotebookProgressBar)
            self.assertEqual(default_progress(None, total=2).total, 2)
            self.assertIsNone(default_progress(False))
        terminal_ipython = types.SimpleNamespace()  # IPython in a terminal: no kernel, no HTML
        with mock.patch.dict(sys.modules, {"IPython": types.SimpleNamespace(get_ipython=lambda: terminal_ipython)}):
            self.assertFalse(in_notebook())


if __name__ == "__main__":
    unittest.main()
