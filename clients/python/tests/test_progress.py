"""cgview_client.ProgressBar: a line per stage or 10% in a log, one redrawn line on a terminal."""
import io
import unittest

from cgview_client import ProgressBar


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


if __name__ == "__main__":
    unittest.main()
