"""The sweep's process, as a command: its stderr, which a reader going away does not stop, and
SIGTERM, which ends it as Ctrl-C does (sweep.main)."""

import contextlib
import signal
import threading


class PipeSafeStream:
    """sys.stderr that a reader going away (`sweep ... 2>&1 | head -1`) does not stop: the
    sweep goes on without its progress lines. Before, the next line raised BrokenPipeError and the
    sweep ended with exit 1, documented as "nothing run", its jobs left pending."""

    def __init__(self, stream):
        self._stream = stream
        self._gone = False

    def write(self, text):
        if not self._gone:
            try:
                return self._stream.write(text)
            except BrokenPipeError:
                self._gone = True
        return len(text)

    def flush(self):
        if not self._gone:
            try:
                self._stream.flush()
            except BrokenPipeError:
                self._gone = True

    def __getattr__(self, name):  # isatty, fileno, encoding: the stream's own
        return getattr(self._stream, name)


def raise_interrupt(signum, frame):
    raise KeyboardInterrupt


@contextlib.contextmanager
def sigterm_as_ctrl_c():
    """SIGTERM (kill, Slurm's scancel, a container's stop) takes Ctrl-C's path: the jobs save
    their checkpoints, the tables are written, and the sweep exits 130, as docs/cli.md says of
    every command. Python's default ends the process by the signal, leaving the jobs' working
    folders and tables as they were. Dask, in this process, installs no handler of its own; the
    jobs' processes get the default back at exec. An ignored SIGTERM stays ignored, as Python
    leaves an ignored SIGINT; the earlier handler is put back after (main called in a program)."""
    if threading.current_thread() is not threading.main_thread():  # only there can it be set
        yield
        return
    old = signal.getsignal(signal.SIGTERM)
    if old == signal.SIG_IGN:
        yield
        return
    signal.signal(signal.SIGTERM, raise_interrupt)
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, old if old is not None else signal.SIG_DFL)
