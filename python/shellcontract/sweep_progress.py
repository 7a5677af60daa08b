"""The sweep's progress: a bar redrawn in place on a terminal (jobs done, failed, left, ETA),
one plain line per finished job otherwise (a log file, a batch system's output)."""

import os
import queue
import sys
import time

BAR_WIDTH = 30
# Outcomes that are a result (counted as done); every other one counts as failed.
RESULT_STATUSES = ("ok", "target not reached")
# Not an outcome: a job not run yet, or one another attempt runs (sweep_job.RUNNING_ELSEWHERE),
# counted as left.
NOT_OUTCOMES = ("pending", "running elsewhere")


def _duration(seconds):
    seconds = int(round(seconds))
    if seconds >= 3600:
        return "{}h{:02d}m".format(seconds // 3600, seconds % 3600 // 60)
    if seconds >= 60:
        return "{}m{:02d}s".format(seconds // 60, seconds % 60)
    return "{}s".format(seconds)


class Progress:
    def __init__(self, total, done=0, failed=0, stream=None, tty=None):
        self.stream = stream or sys.stderr
        # TERM=dumb (Emacs' compile and shell buffers) declares a terminal without the erase
        # sequence the bar is redrawn with: it gets the plain lines, as a file does.
        if tty is None:
            tty = self.stream.isatty() and os.environ.get("TERM") != "dumb"
        self.tty = tty
        self.total = total
        self.done = done
        self.failed = failed
        self.start = time.monotonic()
        self.finished_here = 0  # jobs this process saw end (for the rate)
        self._drawn = False

    def restart_clock(self):
        self.start = time.monotonic()

    @property
    def left(self):
        return self.total - self.done - self.failed

    def eta(self):
        elapsed = time.monotonic() - self.start
        if self.finished_here == 0 or self.left == 0:
            return None
        return elapsed / self.finished_here * self.left

    def line(self):
        eta = self.eta()
        return "{} done, {} failed, {} left{}".format(
            self.done, self.failed, self.left, ", ETA " + _duration(eta) if eta is not None else "")

    def message(self, text):
        """A line of its own (above the bar on a terminal)."""
        if self.tty and self._drawn:
            self.stream.write("\r\033[K")
        self.stream.write(text + "\n")
        self._drawn = False
        if self.tty:
            self.draw()
        self.stream.flush()

    def columns(self):
        """The terminal's width: $COLUMNS when set (a number), else the size of the terminal the
        stream is (asked at each redraw: a window resized), else 80."""
        try:
            return max(1, int(os.environ["COLUMNS"]))
        except (KeyError, ValueError):
            pass
        try:
            return max(1, os.get_terminal_size(self.stream.fileno()).columns)
        except (AttributeError, OSError, ValueError):
            return 80

    def bar_line(self, columns):
        """The bar and its counts in fewer than `columns` characters: a line as wide as the
        terminal or wider wraps, and the redraw's erase (a carriage return, then the rest of the
        row) clears only its last row, leaving a row behind at every redraw. The bar narrows first,
        down to none, then the text is cut."""
        text = self.line()
        room = columns - 1
        width = min(BAR_WIDTH, room - len(text) - 3)  # "[", "] "
        if width >= 5:
            filled = (int(width * (self.done + self.failed) / self.total) if self.total
                      else width)
            return "[{}] {}".format("#" * filled + "." * (width - filled), text)
        return text[:max(0, room)]

    def draw(self):
        if not self.tty:
            return
        self.stream.write("\r\033[K" + self.bar_line(self.columns()))
        self.stream.flush()
        self._drawn = True

    def job_finished(self, record, label):
        if record["status"] in RESULT_STATUSES:
            self.done += 1
        elif record["status"] not in NOT_OUTCOMES:
            self.failed += 1
        if record["status"] not in NOT_OUTCOMES:
            self.finished_here += 1
        text = "{}: {}".format(label, record["status"])
        if record.get("message") and record["status"] not in ("ok",):
            text += " ({})".format(record["message"])
        if self.tty:
            if record["status"] not in RESULT_STATUSES:
                self.message(text)
            else:
                self.draw()
        else:
            self.message("{} -- {}".format(text, self.line()))

    def close(self):
        if self.tty and self._drawn:
            self.stream.write("\n")
            self.stream.flush()
            self._drawn = False


# How often a sweep on a cluster without workers says so again (its jobs wait for the first).
WAIT_NOTE_SECONDS = 60.0


def next_finished(finished, client, scheduler, progress, note_every=WAIT_NOTE_SECONDS):
    """The next finished future; while an existing cluster has no worker, says so every
    `note_every` seconds (it had said so once, at the start, and then waited without a word)."""
    while True:
        try:
            return finished.get(timeout=note_every)
        except queue.Empty:
            if scheduler and not client.scheduler_info().get("workers"):
                progress.message("still no worker on {}: {} jobs wait (start one with `dask worker "
                                 "{}`, or Ctrl-C)".format(scheduler, progress.left, scheduler))
