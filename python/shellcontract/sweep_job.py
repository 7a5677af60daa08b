"""One job of a sweep: `shellcontract run` as a child process, in a folder of its own that is
renamed into DIR/jobs/<id>/ when the job has an outcome (docs/design/sweeps.md).

A child process, not the Python module in the worker: a crash, a run out of memory or a timeout
then ends the job, not the worker, and the job is recorded like any other. This module imports
nothing of the compiled core, so that a worker needs only the CLI and this package's files.
"""

import ctypes
import functools
import json
import numbers
import os
import select
import shutil
import signal
import subprocess
import threading
import time

from . import sweep_checkpoint, sweep_host, sweep_lock, sweep_output
from .sweep_cli import WorkerError, cli_version, describe_worker, find_cli, worker_cli  # noqa: F401
from .sweep_outcome import (CHECKPOINT_NOT_READ, EXIT_STATUS, FINAL_STATUSES,  # noqa: F401
                            INTERRUPTED, OUT_OF_RESOURCES, OUTPUT_NOT_WRITTEN, classify,
                            last_lines)

# Another attempt of the job holds its lock (sweep_lock) and runs it: this one neither ran it nor
# recorded anything. Not an outcome: the job is left, and the attempt that runs it records it.
RUNNING_ELSEWHERE = "running elsewhere"
# How long a child asked to stop (SIGTERM: it writes its checkpoint) may take before SIGKILL.
STOP_GRACE_SECONDS = 10.0
# How long an attempt waits for the job's lock: an attempt that was stopped (a lost worker's, whose
# run got the parent-death signal) saves and ends within STOP_GRACE_SECONDS, and Dask's
# reschedule of it then resumes from its checkpoint. A lock held longer is a run that goes on.
JOB_LOCK_WAIT_SECONDS = STOP_GRACE_SECONDS + 5
# The longest wait or timeout a sweep takes (about 31 years): far beyond any job, and within what
# the waits can take (select's and a queue's timeouts overflow near 9.2e9 s).
MAX_SECONDS = 1e9
SUMMARY_FIELDS = ("final_volume_ratio", "frames_run", "new_intersections", "peak_memory_mb")


try:  # loaded here, not in the forked child (where only the call itself should run)
    _PRCTL = ctypes.CDLL(None, use_errno=True).prctl
except (OSError, AttributeError):
    _PRCTL = None
PR_SET_PDEATHSIG = 1


# How a job's process ends when its starter was gone before the parent-death signal was set
# (128 + SIGTERM, as that signal would have ended it; nobody waits for it).
ORPHAN_EXIT = 128 + int(signal.SIGTERM)


def _die_with_parent(parent):
    """In the child before exec: SIGTERM when the thread that started it ends (a worker killed
    mid-job), so that the run writes its checkpoint and stops instead of running on orphaned.
    `parent`: the starter's pid. A starter that died before the signal was set (killed while it
    started the job) never sends it: the child then ends here instead of running the job."""
    if _PRCTL is not None:
        _PRCTL(PR_SET_PDEATHSIG, int(signal.SIGTERM))
    if os.getppid() != parent:
        os._exit(ORPHAN_EXIT)


# The same check after setpriv has set the signal, in the shell that then execs the run ($1: the
# starter's pid; dash and bash read $PPID once, at their start, which is after the prctl).
_PARENT_CHECK = 'test "$PPID" = "$1" || exit {}; shift; exec "$@"'.format(ORPHAN_EXIT)

_SETPRIV = None  # [] when setpriv cannot set the parent-death signal


def _death_signal_prefix():
    """The same parent-death signal set by util-linux's setpriv, which then execs a shell that
    runs the job only if its starter (this process) is still its parent: a starter killed between
    the start of the child and setpriv's prctl (a sweep killed as it starts a job: the moment a
    test that kills a sweep after its first jobs finish hits) sends no signal, and the job ran to
    its end orphaned, holding its attempt's lock while the next sweep started. [] where setpriv
    cannot set it. Preferred to Popen's preexec_fn: a preexec_fn makes Python fork the whole
    calling process (its page tables copied, Python code run in the copy) instead of
    vfork-and-exec, which costs a job more than all the rest of the engine; an exec more, as
    setpriv's own, costs far less (lab/sweep/README.md)."""
    global _SETPRIV
    if _SETPRIV is None:
        exe = shutil.which("setpriv")
        exe = exe and os.path.abspath(exe)  # a job runs in its own folder, not this one's
        prefix = [exe, "--pdeathsig", "TERM", "--"] if exe else []
        usable = False
        if exe:  # tried once: an old setpriv without the option, or one refused it, exits 1
            try:
                r = subprocess.run(prefix + [exe, "--help"], capture_output=True, text=True,
                                   timeout=10)
                usable = r.returncode == 0 and "--pdeathsig" in r.stdout
            except (OSError, subprocess.SubprocessError):
                usable = False
        _SETPRIV = prefix if usable else []
    if not _SETPRIV:
        return []
    return _SETPRIV + ["/bin/sh", "-c", _PARENT_CHECK, "shellcontract-job", str(os.getpid())]


# The jobs this Python process runs now, by sweep (a token per sweep command): their processes,
# and how many run_job calls are under way. An embedded cluster's workers are threads of the
# sweep's process, so on Ctrl-C the sweep stops them itself (stop_running, then wait_stopped); on
# an existing cluster it asks every worker to do the same (Client.run). A token, not the whole
# process: a worker of a shared cluster may hold another sweep's jobs, which go on.
_RUNNING = {}  # Popen -> sweep token
_RUNNING_LOCK = threading.Lock()
_STOPPED = set()  # sweep tokens told to stop: none of their jobs starts any more
_ACTIVE = threading.Condition()
_active_calls = {}  # sweep token -> run_job calls under way


def stop_running(sweep=None):
    """SIGTERM to every job process of the sweep `sweep` (None: of every sweep) started here that
    still runs: each saves its checkpoint and exits (its run_job then returns an 'interrupted'
    record). No job of that sweep starts after this, so that a task a worker takes up meanwhile
    does not slip through. Returns how many run_job calls of it are under way."""
    with _RUNNING_LOCK:
        _STOPPED.add(sweep)
        procs = [p for p, token in _RUNNING.items() if sweep is None or token == sweep]
    for proc in procs:
        if proc.poll() is None:
            try:
                proc.terminate()
            except OSError:
                pass
    return active_calls(sweep)


def allow_starting(sweep=None):
    with _RUNNING_LOCK:
        _STOPPED.discard(sweep)


def _is_stopped(sweep):
    return None in _STOPPED or sweep in _STOPPED


def active_calls(sweep=None):
    """How many run_job calls of the sweep `sweep` (None: of any) are under way here."""
    with _ACTIVE:
        return sum(n for token, n in _active_calls.items() if sweep is None or token == sweep)


def wait_stopped(timeout, sweep=None):
    """Waits until no run_job call of the sweep `sweep` (None: of any) is under way in this
    process (at most `timeout` seconds); True if none is."""
    with _ACTIVE:
        return _ACTIVE.wait_for(lambda: not any(
            n for token, n in _active_calls.items() if sweep is None or token == sweep), timeout)


paths = sweep_checkpoint.paths
clean_stale_attempts = sweep_lock.clean_stale_attempts


def read_record(out_dir, job_id):
    """The job's record (DIR/jobs/<id>/job.json), or None."""
    try:
        with open(os.path.join(out_dir, "jobs", job_id, "job.json")) as f:
            return json.load(f)
    except (OSError, ValueError):
        return None


def is_done(record):
    return record is not None and record.get("status") in FINAL_STATUSES


def seconds(name, value, zero=True):
    """`value` as a float number of seconds in [0, MAX_SECONDS] ((0, MAX_SECONDS] unless `zero`);
    a ValueError naming the parameter `name` otherwise (NaN, inf, a negative, not a number)."""
    ok = isinstance(value, numbers.Real) and not isinstance(value, bool)
    v = float(value) if ok else None
    if v is None or not (0 <= v if zero else 0 < v) or not v <= MAX_SECONDS:
        raise ValueError("{}: expected a number of seconds {} 0 and <= {:g}, got {!r}".format(
            name, ">=" if zero else ">", MAX_SECONDS, value))
    return v


def run_job(job, out_dir, cli, timeout=None, checkpoint_every=20, sweep=None, own_cli=None,
            version=None, threads=None, share=None, lock_wait=JOB_LOCK_WAIT_SECONDS):
    """Runs one job (a Job.to_dict()) unless DIR/jobs/<id>/ holds its outcome already; returns
    its record. An interrupted job (SIGTERM/SIGINT to the child) leaves its checkpoint and no
    record; the next attempt resumes from the checkpoint.

    `sweep` is the sweep's token (stop_running). `own_cli` not None: a worker of an existing
    cluster, which runs worker_cli(cli, version, own_cli) (its own executable if `own_cli`, else
    the client's `cli`, of the sweep's version); None: `cli` as it is (this machine's).
    `threads`: the job's --threads unless its options give one (sweep_host.job_threads); None: the
    tool's default. `share` (an existing cluster's, sweep_host.cluster_share): `threads` is this
    worker's machine's share instead (sweep_host.worker_job_threads). `lock_wait`: how long
    this attempt waits for another attempt of the job that holds its lock (seconds, >= 0)."""
    lock_wait = seconds("lock_wait", lock_wait)
    with _ACTIVE:
        _active_calls[sweep] = _active_calls.get(sweep, 0) + 1
    try:
        if own_cli is not None:
            cli = worker_cli(cli, version, own_cli)
        if threads is None and share is not None:
            threads = sweep_host.worker_job_threads(share)
        return _run_job(job, out_dir, cli, timeout, checkpoint_every, sweep, threads, lock_wait)
    finally:
        with _ACTIVE:
            _active_calls[sweep] -= 1
            if not _active_calls[sweep]:
                del _active_calls[sweep]
            _ACTIVE.notify_all()


def _not_run(job, status, message):
    return {"job": job["id"], "mesh": job["mesh"], "options": job["options"], "status": status,
            "exit_code": None, "message": message, "resumed": False, "output": ""}


def _run_job(job, out_dir, cli, timeout, checkpoint_every, sweep, threads=None,
             lock_wait=JOB_LOCK_WAIT_SECONDS):
    out_dir = os.path.abspath(out_dir)
    p = paths(out_dir, job["id"])
    old = read_record(out_dir, job["id"])
    if is_done(old):
        remove_checkpoint(out_dir, job["id"])
        old["skipped"] = True
        return old
    os.makedirs(os.path.dirname(p["checkpoint"]), exist_ok=True)
    os.makedirs(os.path.join(out_dir, "jobs"), exist_ok=True)
    # Another attempt of the job may be running it (the same sweep twice at once, a rerun while
    # an earlier cluster's jobs run, a lost worker's run still saving): its lock says so, and
    # this attempt then neither runs the tool (which would refuse the checkpoint's lock, exit 1)
    # nor records an outcome nor removes the job's files.
    deadline = time.monotonic() + lock_wait
    note = None
    while True:
        job_fd = sweep_lock.lock_job(out_dir, job["id"], deadline, lambda: _is_stopped(sweep))
        if job_fd is None:
            if _is_stopped(sweep):
                return _not_run(job, "interrupted", "not started")
            return _not_run(job, RUNNING_ELSEWHERE, (
                "another attempt of this job runs it, holding {}; its outcome is kept when it "
                "ends").format(sweep_lock.job_lock_path(out_dir, job["id"])))
        try:
            record, note = _run_locked(job, out_dir, cli, timeout, checkpoint_every, sweep, p,
                                       job_fd, threads)
        finally:
            sweep_lock.release_job(out_dir, job["id"], job_fd)
        if record is not None:
            return record
        # The tool's own lock was held: a run of the job that outlived its attempt's lock (where
        # the file system passes one lock and not the other). Its end is waited for as above.
        if _is_stopped(sweep):
            return _not_run(job, "interrupted", "not started")
        if time.monotonic() >= deadline:
            return _not_run(job, RUNNING_ELSEWHERE, "another run of this job holds its "
                                                    "checkpoint; its outcome is kept when it "
                                                    "ends ({})".format(note))
        time.sleep(0.5)


def _run_locked(job, out_dir, cli, timeout, checkpoint_every, sweep, p, job_fd, threads):
    """The job's attempts while this one holds its lock: (record, None), or (None, the tool's
    message) when the tool found its own lock of the checkpoint held."""
    old = read_record(out_dir, job["id"])
    if is_done(old):  # the attempt that held the lock finished the job
        sweep_checkpoint.remove_files(out_dir, job["id"])
        old["skipped"] = True
        return old, None
    note = None
    while True:
        name, lock_fd = sweep_lock.lock_attempt(p["work"], job["id"])
        try:
            result = _run_attempt(job, out_dir, cli, timeout, checkpoint_every, sweep, p,
                                  os.path.join(p["work"], name), (lock_fd, job_fd), threads, note)
        finally:
            sweep_lock.release_attempt(p["work"], name, lock_fd)
        if isinstance(result, dict):
            return result, None
        kind, note = result
        if kind == "held":
            return None, note
        # "refused": the checkpoint was removed; once more from the first frame


def _run_attempt(job, out_dir, cli, timeout, checkpoint_every, sweep, p, work, lock_fds,
                 threads=None, note=None):
    """The job's record; or ("refused", the tool's message) when the tool refused the job's
    checkpoint, which is then removed: the caller runs the job again without it; or ("held", the
    tool's message) when another run held the checkpoint's lock. `note` heads the attempt's
    messages. `lock_fds`: the attempt's and the job's locks, which the job's process inherits."""
    os.makedirs(work)
    ext = os.path.splitext(job["mesh"])[1].lower() or ".off"
    mesh_name = os.path.splitext(os.path.basename(job["mesh"]))[0] + ext
    # The outputs by their names in the attempt folder, the process's working folder: the
    # summary records them as given, and the folder is renamed to jobs/<id>/ once the job has an
    # outcome, so a path through it would name a folder that is gone (and differ between two
    # sweeps of the same job). `--output=NAME`: a name beginning with '-' is not an option.
    cmd = [cli, "run", job["mesh"], "--output=" + mesh_name, "--log=log.csv",
           "--summary=summary.json",
           "-q", "--checkpoint", p["checkpoint"], "--checkpoint-every", str(checkpoint_every)]
    resumed = os.path.isfile(p["checkpoint"])
    if resumed:
        cmd += ["--resume", p["checkpoint"]]
    cmd += list(job["args"])
    if threads is not None and "--threads" not in job["args"]:
        cmd += ["--threads", str(threads)]
    start = time.monotonic()
    timed_out = False
    with open(os.path.join(work, "messages.txt"), "wb") as messages:
        if note is not None:
            messages.write(("shellcontract sweep: the job's checkpoint was refused ({}); it was "
                            "removed and the job ran from its first frame\n".format(note)).encode())
            messages.flush()
        # A session of its own: a Ctrl-C at the terminal reaches the sweep, which stops the
        # children itself (SIGTERM: they write their checkpoints).
        prefix = _death_signal_prefix()
        with _RUNNING_LOCK:
            # The job's process inherits the attempt's and the job's locks (pass_fds), so that
            # its folder is in use, and the job running, as long as the process runs, even after
            # this one is gone (a worker killed).
            proc = None if _is_stopped(sweep) else subprocess.Popen(
                prefix + cmd, stdin=subprocess.DEVNULL, stdout=messages, stderr=messages,
                cwd=work, start_new_session=True,
                preexec_fn=None if prefix else functools.partial(_die_with_parent, os.getpid()),
                pass_fds=lock_fds)
            if proc is not None:
                _RUNNING[proc] = sweep
        if proc is None:  # the sweep is stopping: the job is left for the next one
            shutil.rmtree(work, ignore_errors=True)
            return _not_run(job, "interrupted", "not started")
        try:
            cpu = None
            try:
                rc, cpu = _wait(proc, timeout)
            except subprocess.TimeoutExpired:
                timed_out = True
                rc = _stop(proc)
        except BaseException:
            _stop(proc)
            shutil.rmtree(work, ignore_errors=True)
            raise
        finally:
            with _RUNNING_LOCK:
                _RUNNING.pop(proc, None)
    wall = time.monotonic() - start
    if rc == 1:  # another run holds the checkpoint's lock: not this job's outcome
        held = sweep_checkpoint.held_by_another_run(work, p["checkpoint"])
        if held is not None:
            shutil.rmtree(work, ignore_errors=True)
            return "held", held
    # The checkpoint is the sweep's own (.work/checkpoints), not the job's input: one the tool
    # will not resume from (damaged, or written by another run) made the job a final "bad input"
    # that every later sweep skipped. One it could not read is kept for the next sweep.
    error = (sweep_checkpoint.checkpoint_error(work, p["checkpoint"])
             if resumed and rc == 2 else None)
    if error is not None and error[0] == "refused":
        if not sweep_checkpoint.remove_files(out_dir, job["id"]):
            shutil.rmtree(work, ignore_errors=True)
            return "held", error[1]
        if not os.path.exists(p["checkpoint"]):
            shutil.rmtree(work, ignore_errors=True)
            return "refused", error[1]
    summary = None
    try:
        with open(os.path.join(work, "summary.json")) as f:
            summary = json.load(f)
    except (OSError, ValueError):
        pass
    tool_lines = [line.decode("utf-8", "replace")
                  for line in sweep_checkpoint.tool_lines(work)]
    status, message = classify(rc, timed_out, summary,
                               last_lines(os.path.join(work, "messages.txt")), tool_lines)
    if error is not None and error[0] == "not read":
        status, message = CHECKPOINT_NOT_READ, (
            "the job's checkpoint could not be read; it is kept, and the next sweep tries to "
            "resume from it again (remove {} to run the job from its first frame instead) "
            "({})".format(p["checkpoint"], error[1]))
    record = {"job": job["id"], "mesh": job["mesh"], "options": job["options"],
              "status": status, "exit_code": rc, "message": message,
              "wall_seconds": round(wall, 3),
              "cpu_seconds": None if cpu is None else round(cpu, 3),
              "resumed": resumed, "output": ""}
    for k in SUMMARY_FIELDS:
        record[k] = summary.get(k) if summary else None
    if status == "interrupted":
        shutil.rmtree(work, ignore_errors=True)
        return record
    if os.path.isfile(os.path.join(work, mesh_name)):
        record["output"] = os.path.join("jobs", job["id"], mesh_name)
    sweep_output.write_atomic(os.path.join(work, "job.json"),
                              json.dumps(record, indent=1, sort_keys=True) + "\n")
    _publish(work, p["final"], out_dir)
    if status in FINAL_STATUSES:
        sweep_checkpoint.remove_files(out_dir, job["id"])
    return record


def remove_checkpoint(out_dir, job_id):
    """The files a finished job kept in DIR/.work/checkpoints (sweep_checkpoint.remove_files),
    unless another attempt of the job holds its lock."""
    sweep_checkpoint.remove_done(out_dir, [job_id])


def _wait(proc, timeout):
    """Waits for the job's process: (its exit status as Popen's returncode, its CPU seconds, user
    and system, or None where they cannot be had). With a timeout, a pidfd (Linux 5.3), which
    becomes readable when the process ends, instead of Popen.wait(timeout), which wakes up
    every few milliseconds to look."""
    if timeout is not None:
        try:
            fd = os.pidfd_open(proc.pid)
        except (AttributeError, OSError):  # no pidfd here: Popen's own polling
            fd = None
            proc.wait(timeout=timeout)
        if fd is not None:
            try:
                ready, _, _ = select.select([fd], [], [], timeout)
            finally:
                os.close(fd)
            if not ready:
                raise subprocess.TimeoutExpired(proc.args, timeout)
    if proc.returncode is None:
        try:
            _, status, usage = os.wait4(proc.pid, 0)
        except ChildProcessError:  # reaped by a poll() in another thread (stop_running)
            return proc.wait(), None
        rc = os.waitstatus_to_exitcode(status)
        proc.returncode = rc  # (a poll() elsewhere, finding no child, could overwrite it)
        return rc, usage.ru_utime + usage.ru_stime
    return proc.returncode, None


def _stop(proc):
    """SIGTERM (the run writes its checkpoint), then SIGKILL after STOP_GRACE_SECONDS."""
    if proc.poll() is None:
        proc.terminate()
        try:
            proc.wait(timeout=STOP_GRACE_SECONDS)
        except subprocess.TimeoutExpired:
            proc.kill()
    return proc.wait()


def _publish(work, final, out_dir):
    """Renames the finished folder to DIR/jobs/<id>/ (one rename: whole or absent). An earlier
    outcome that is not final (a crash) is moved aside first; one that is final (another attempt
    of the same job finished first, e.g. after a worker was lost) is kept and ours dropped."""
    if os.path.isdir(final):
        if is_done(read_record(out_dir, os.path.basename(final))):
            shutil.rmtree(work, ignore_errors=True)
            return
        trash = work + ".old"
        try:
            os.rename(final, trash)
            shutil.rmtree(trash, ignore_errors=True)
        except OSError:
            pass
    try:
        os.rename(work, final)
    except OSError:  # another attempt's outcome arrived in between: keep it
        shutil.rmtree(work, ignore_errors=True)
