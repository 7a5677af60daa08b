"""What the sweep's own process has to work with (docs/design/sweeps.md, "Where the jobs run",
"Progress"): the cores it may use, how many threads each job takes when several run at once, and
a stderr that exists. Imports nothing of the compiled core."""

import os
import sys

from . import sweep_process


# Where the cgroup file systems and this process's cgroups are read (the tests point them at a
# tree of their own).
CGROUP_ROOT = "/sys/fs/cgroup"
PROC_SELF_CGROUP = "/proc/self/cgroup"


def _first_line(path):
    try:
        with open(path, "rb") as f:
            return f.read(256).split(b"\n", 1)[0].decode("ascii")
    except (OSError, UnicodeDecodeError):
        return ""


def _whole_integer(text):
    """A decimal integer and nothing else but surrounding blanks, or None (int() would also take
    '1_000' and other digits than ASCII's)."""
    text = text.strip(" \t\r")
    digits = text[1:] if text.startswith("-") else text
    if not digits or not all("0" <= c <= "9" for c in digits):
        return None
    return int(text)


def _cpus_of(quota, period):
    """ceil(quota / period) CPUs; 0 (no quota) unless both are positive (v1 writes -1 for none)."""
    if quota is None or period is None or quota <= 0 or period <= 0:
        return 0
    return -(-quota // period)


def _v2_limit(folder):
    """cgroup v2: cpu.max is "QUOTA PERIOD", or "max PERIOD" for none."""
    parts = _first_line(os.path.join(folder, "cpu.max")).split(" ")
    if len(parts) != 2:
        return 0
    return _cpus_of(_whole_integer(parts[0]), _whole_integer(parts[1]))


def _v1_limit(folder):
    """cgroup v1: the cpu controller's cpu.cfs_quota_us (-1 for none) and cpu.cfs_period_us."""
    return _cpus_of(_whole_integer(_first_line(os.path.join(folder, "cpu.cfs_quota_us"))),
                    _whole_integer(_first_line(os.path.join(folder, "cpu.cfs_period_us"))))


def _tighter(a, b):
    return b if a <= 0 else a if b <= 0 else min(a, b)


def _tightest_along(base, path, limit_of):
    """The tightest limit of the cgroup `path` ("/a/b") under the mount `base` and of each
    ancestor found there, down to `base` itself: a parent's quota holds its children too, and a
    container whose cgroup is mounted as the root has its own limit there, not under its path."""
    parts = [p for p in path.split("/") if p not in ("", ".")]
    if ".." in parts:  # not a path the kernel writes: nothing outside the mount is read
        return 0
    best = 0
    for n in range(len(parts) + 1):
        folder = os.path.join(base, *parts[:n])
        if os.path.isdir(folder):
            best = _tighter(best, limit_of(folder))
    return best


def cgroup_cpu_limit(root=None, proc_self_cgroup=None):
    """The CPU quota of a process whose /proc/self/cgroup reads `proc_self_cgroup` (None: this
    process's), the cgroup file systems mounted at `root` (None: CGROUP_ROOT): ceil(quota /
    period) of the tightest quota on its cgroup or any ancestor, v2 (cpu.max) and v1
    (cpu.cfs_quota_us / cpu.cfs_period_us of the cpu controller's hierarchy) alike; 0 when none
    is set or none can be read (a missing or malformed file is no quota, never an error). The
    same reading as the tool's own default thread count (src/core/usable_cpus.cpp)."""
    root = CGROUP_ROOT if root is None else root
    if proc_self_cgroup is None:
        try:
            with open(PROC_SELF_CGROUP, "rb") as f:
                proc_self_cgroup = f.read(1 << 16).decode("utf-8", "replace")
        except OSError:
            return 0
    best = 0
    for line in proc_self_cgroup.split("\n"):
        fields = line.split(":", 2)  # ID:CONTROLLERS:PATH; the path may hold colons
        if len(fields) != 3 or not fields[2].startswith("/"):
            continue
        hierarchy, controllers, path = fields
        if hierarchy == "0" and controllers == "":  # v2, the unified hierarchy at the root
            best = _tighter(best, _tightest_along(root, path, _v2_limit))
        elif "/" not in controllers and "cpu" in controllers.split(","):
            # v1: the cpu controller's hierarchy, at root/cpu (a link where it is shared with
            # cpuacct) or at root/<its controllers>, "cpu,cpuacct".
            for base in (os.path.join(root, "cpu"), os.path.join(root, controllers)):
                if os.path.isdir(base):
                    best = _tighter(best, _tightest_along(base, path, _v1_limit))
                    break
    return best


def usable_cores():
    """The cores this process may use, as the tool's own default thread count is: its CPU
    affinity (taskset, a Slurm or container cpuset) held to its cgroup's CPU quota (docker
    --cpus, a Kubernetes CPU limit: cgroup_cpu_limit). os.cpu_count() counts every core of the
    machine, so a sweep given 4 cores of a 128-core node started 128 jobs on those 4; the
    affinity alone does not see a quota, so a container given 2 CPUs of 64 started 64."""
    try:
        cores = max(1, len(os.sched_getaffinity(0)))
    except (AttributeError, OSError):  # no affinity on this system (macOS)
        cores = os.cpu_count() or 1
    quota = cgroup_cpu_limit()
    return min(cores, quota) if quota > 0 else cores


# The most workers of the embedded cluster (--workers, and the default on a machine of more
# cores). Its workers are threads of the sweep's process, each with its connection and heartbeat
# to the scheduler on one event loop: on a small machine a thousand of them did not finish
# starting (handshakes timed out, the one job stayed pending, tens of thousands of lines of
# Dask's tracebacks). Nothing is lost on a machine of more cores: the jobs at once share them
# (job_threads), each with several threads.
MAX_WORKERS = 256


def embedded_workers(asked, jobs):
    """The workers of the embedded cluster for `jobs` jobs to run: `asked` (--workers; None: the
    usable cores, held to MAX_WORKERS), but no more than the jobs, since a worker without a job
    would only take its share of the start and the heartbeats."""
    return max(1, min(asked or min(usable_cores(), MAX_WORKERS), jobs))


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


def cluster_share(workers, jobs):
    """What a job on an existing cluster needs to know to take its share of its machine
    (worker_job_threads): for each worker (`workers`: Client.scheduler_info()["workers"]), how
    many jobs may run at once on its machine, the threads of every worker on its host (Dask runs
    a task on each worker thread) but no more than the sweep's `jobs`; and `jobs`. A machine,
    not a worker: the usual cluster (docs/design/sweeps.md) has as many single-threaded workers
    on each machine as it has cores, so one worker's own nthreads, 1, would give each job every
    core and N jobs N x N threads."""
    def host(address, info):
        return info.get("host") or address
    per_host = {}
    for address, info in workers.items():
        per_host[host(address, info)] = (per_host.get(host(address, info), 0)
                                         + max(1, int(info.get("nthreads") or 1)))
    return {address: min(jobs, per_host[host(address, info)])
            for address, info in workers.items()}, jobs


def worker_job_threads(share, cores=None):
    """In a job's task on a worker of an existing cluster: the job's --threads, job_threads of
    the jobs at once on this worker's machine (cluster_share; a worker that joined after the jobs
    were handed out counts its own threads) and of the cores this worker may use (its affinity and
    quota, where jobs of all the machine's workers run). None outside a worker's task."""
    slots, jobs = share
    try:
        from distributed import get_worker
        worker = get_worker()
    except (ImportError, ValueError):
        return None
    return job_threads(slots.get(worker.address) or worker.nthreads, jobs, cores)


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
