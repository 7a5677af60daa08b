"""The sweep's process, as a command: its stderr, which a reader going away does not stop, and
SIGTERM, SIGHUP and SIGUSR1, which end it as Ctrl-C does (sweep.main)."""

import contextlib
import os
import signal
import threading



def point_at_devnull(stream):
    """Points `stream`'s descriptor at /dev/null, where it can (a stream whose writes failed:
    Python's own flush at exit would fail again, a traceback and exit 120)."""
    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        try:
            os.dup2(devnull, stream.fileno())
        finally:
            os.close(devnull)
    except (OSError, ValueError, AttributeError):
        pass

class PipeSafeStream:
    """sys.stderr whose failing writes do not stop the sweep: a reader going away (`sweep ... 2>&1
    | head -1`), a full disk or quota under a log (`2>>sweep.log`, `2>/dev/full`: ENOSPC, EDQUOT,
    EFBIG, EIO). The sweep goes on without its progress lines, and its exit code is its jobs'
    (lost messages are no job's failure). Before, the next line raised, and the sweep ended with
    exit 1, documented as "nothing run", its jobs left pending; a full disk under stderr was also
    named as the results folder's error."""

    def __init__(self, stream):
        self._stream = stream
        self._gone = False

    def write(self, text):
        if not self._gone:
            try:
                return self._stream.write(text)
            except (OSError, ValueError):  # ValueError: the stream closed under it
                self._lost()
        return len(text)

    def flush(self):
        if not self._gone:
            try:
                self._stream.flush()
            except (OSError, ValueError):
                self._lost()

    def _lost(self):
        """Nothing more is written: the stream's buffer, which holds what failed, is emptied
        where it can be (else its flush at exit fails again), and later writes are dropped."""
        self._gone = True
        # A TextIOWrapper's buffered writer keeps what it could not write; writing to a
        # detached descriptor-less buffer is not possible, so the stream is pointed at
        # /dev/null for Python's own flush at exit.
        point_at_devnull(self._stream)

    def __getattr__(self, name):  # isatty, fileno, encoding: the stream's own
        return getattr(self._stream, name)


class StopRequest:
    """The sweep's handler of SIGINT and the stop signals: the first raises KeyboardInterrupt in
    the main thread, which takes Ctrl-C's path (its tasks cancelled, its jobs told to stop, each
    saving its checkpoint, then the tables and exit 130). A later one is that stop under way, not
    a new request: one request often comes as several signals (a service manager's SIGTERM then
    SIGHUP, a batch system's SIGUSR1 to the sweep and then SIGTERM, a second Ctrl-C), and raised
    again inside the stop sequence it cut it short: the sweep hung on jobs it had not yet told to
    stop, which later ended without their checkpoints. The stop ends within the jobs' grace
    (sweep_job.STOP_GRACE_SECONDS); SIGKILL ends the sweep at once (its jobs still save: the
    parent-death signal)."""

    def __init__(self):
        self.stopping = False

    def __call__(self, signum, frame):
        if self.stopping:
            return
        self.stopping = True
        raise KeyboardInterrupt


# The signals that stop the sweep as Ctrl-C does, besides SIGINT: those the CLI stops on alike
# (INTERRUPT_SIGNALS, src/mesh/file_safety.hpp; docs/cli.md, exit code 130). SIGHUP: the terminal
# or ssh session closed; SIGUSR1: Slurm's warning before the time limit (`sbatch --signal`).
# Before, only SIGTERM was taken: SIGHUP or SIGUSR1 ended the sweep by the signal, its tables
# not written and its jobs' working folders left behind.
STOP_SIGNALS = (signal.SIGTERM, signal.SIGHUP, signal.SIGUSR1)


@contextlib.contextmanager
def stop_signals_as_ctrl_c():
    """SIGTERM (kill, Slurm's scancel, a container's stop), SIGHUP and SIGUSR1 take Ctrl-C's
    path: the jobs save their checkpoints, the tables are written, and the sweep exits 130, as
    docs/cli.md says of every command; any of them (SIGINT too) after the first is part of that
    stop (StopRequest). Python's default ends the process by the signal, leaving
    the jobs' working folders and tables as they were. Dask, in this process, installs no handler
    of its own; the jobs' processes get the default back at exec. An ignored signal stays
    ignored, as Python leaves an ignored SIGINT; the earlier handlers are put back after (main
    called in a program)."""
    if threading.current_thread() is not threading.main_thread():  # only there can they be set
        yield
        return
    old = {}
    handler = StopRequest()
    try:
        for sig in (signal.SIGINT,) + STOP_SIGNALS:
            before = signal.getsignal(sig)
            if before == signal.SIG_IGN:
                continue
            signal.signal(sig, handler)
            old[sig] = before
        yield
    finally:
        for sig, before in old.items():
            signal.signal(sig, before if before is not None else signal.SIG_DFL)
