"""What the sweep's own process has to work with (docs/design/sweeps.md, "Where the jobs run",
"Progress"): the cores it may use, how many threads each job takes when several run at once, and
a stderr that exists. Imports nothing of the compiled core."""

import os
import sys

from . import sweep_process


def usable_cores():
    """The cores this process may run on: its CPU affinity (taskset, a Slurm or container cpuset),
    as the tool's own thread count is; os.cpu_count() counts every core of the machine, so a
    sweep given 4 cores of a 128-core node started 128 jobs on those 4."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except (AttributeError, OSError):  # no affinity on this system (macOS)
        return os.cpu_count() or 1


def job_threads(workers, jobs, cores=None):
    """The --threads of each job when `workers` jobs at a time run `jobs` jobs on the embedded
    cluster: the usable cores shared out among the jobs that run at once, at least 1; None (the
    tool's default, every usable core) when one job runs at a time. Each job's tool would
    otherwise start a thread per core, so N jobs at once ran N x N threads on N cores (a
    container's process limit counts them all). A job whose options give `threads` keeps it
    (sweep_job.run_job). The result does not depend on it, nor does the job's id (`threads` is
    result-neutral), and a checkpoint resumes with any thread count."""
    at_once = min(workers, jobs)
    if at_once <= 1:
        return None
    return max(1, (cores or usable_cores()) // at_once)


class _Discard:
    """A stderr that takes and drops everything (the process was started without one)."""

    def write(self, text):
        return len(text)

    def flush(self):
        pass

    def isatty(self):
        return False


def guard_stderr():
    """sys.stderr made one that the sweep can write to whatever it was started with. Fd 2 closed
    (`2>&-`, a daemon's or launcher's child): /dev/null takes fd 2, so that no file the sweep
    opens later lands there to receive what a library writes to stderr; sys.stderr None (so
    Python sets it when fd 2 was closed, or a program that has none): the messages and the
    progress are dropped and the jobs run. Before, the sweep ended with exit 120 before any job,
    every job left pending. A reader going away is taken care of by PipeSafeStream."""
    try:
        os.fstat(2)
    except OSError:
        fd = os.open(os.devnull, os.O_WRONLY)
        if fd != 2:
            os.dup2(fd, 2)
            os.close(fd)
    if sys.stderr is None:
        sys.stderr = _Discard()
    if not isinstance(sys.stderr, sweep_process.PipeSafeStream):
        sys.stderr = sweep_process.PipeSafeStream(sys.stderr)
