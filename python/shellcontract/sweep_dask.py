"""The sweep's Dask cluster: an embedded local one, or an existing one (--scheduler) whose workers
are checked first, and the running of the jobs on it (shellcontract.sweep; docs/design/sweeps.md).
"""

import errno
import fcntl
import os
import queue
import sys
import tempfile

from . import sweep_cli, sweep_host, sweep_job, sweep_progress


class Interrupted(Exception):
    """Ctrl-C: the sweep stopped its jobs; `still_running` jobs (None: unknown) had not ended
    when it gave up waiting."""

    def __init__(self, still_running=0):
        super().__init__(still_running)
        self.still_running = still_running


class JobsStopped(Exception):
    """An error other than Ctrl-C ended the running of the jobs (`error`: the results tables
    could not be written, the scheduler went away); the sweep stopped its jobs first, as for
    Ctrl-C, and `still_running` (None: unknown) had not ended when it gave up waiting."""

    def __init__(self, error, still_running=0):
        super().__init__(error, still_running)
        self.error = error
        self.still_running = still_running


class WorkersUnusable(Exception):
    """An existing cluster's workers that cannot run the jobs (the message says which, why)."""


class ClusterFailed(Exception):
    """The embedded cluster did not start (no job ran); the message says why."""


def _errno_of(e):
    """The errno of an OSError `e` or of one that caused it (Dask wraps its start's errors)."""
    seen = 0
    while e is not None and seen < 10:
        if isinstance(e, OSError) and e.errno is not None:
            return e.errno
        e = e.__cause__ or e.__context__
        seen += 1
    return None


SCRATCH_PREFIX = "shellcontract-sweep-dask-"
# In each scratch folder, locked (flock) by its sweep for as long as it runs.
SCRATCH_LOCK = "sweep.lock"


class _Scratch:
    """A folder of the sweep's own for its workers' scratch folders (Dask's
    dask-worker-space/worker-*), in Dask's temporary folder (its temporary-directory setting,
    else the system's, as Dask's own), removed whole at the end (remove). Dask removes its
    workers' folders itself, but not when the process is out of descriptors (`ulimit -n`: "Failed
    to remove ...", or a worker that failed to start and took no lock), and in the shared
    dask-worker-space such a folder stayed for good. A cluster that failed to start may still
    hold every descriptor: the descriptor of the folder's lock is the one kept for the removal.
    The folder of a sweep killed with SIGKILL is removed by the next sweep's (purge_stale)."""

    def __init__(self):
        import dask
        self._reserve = None
        self.path = tempfile.mkdtemp(prefix=SCRATCH_PREFIX,
                                     dir=dask.config.get("temporary-directory", None) or None)
        try:
            # Locked before it has its name, so that no other sweep's purge_stale can take the
            # lock of a folder being made.
            making = os.path.join(self.path, SCRATCH_LOCK + ".new")
            self._reserve = os.open(making, os.O_RDWR | os.O_CREAT | os.O_EXCL, 0o600)
            try:
                fcntl.flock(self._reserve, fcntl.LOCK_EX | fcntl.LOCK_NB)
                os.rename(making, os.path.join(self.path, SCRATCH_LOCK))
            except OSError:  # no locks on this file system: nothing purged, nothing mistaken
                pass
        except BaseException:
            self.remove()
            raise
        purge_stale(os.path.dirname(self.path), self.path)

    def remove(self):
        if self._reserve is not None:
            os.close(self._reserve)
            self._reserve = None
        _remove_tree(self.path)


def purge_stale(base, own=None):
    """Removes the scratch folders in `base` of sweeps that ended without removing theirs (killed
    with SIGKILL): this user's, whose lock no process holds. A folder without its lock (being
    made, or made where there are no locks) is left."""
    try:
        names = os.listdir(base)
    except OSError:
        return
    for name in names:
        path = os.path.join(base, name)
        if not name.startswith(SCRATCH_PREFIX) or path == own:
            continue
        try:
            if os.lstat(path).st_uid != os.geteuid():
                continue
            fd = os.open(os.path.join(path, SCRATCH_LOCK), os.O_RDWR | os.O_NOFOLLOW)
        except OSError:
            continue
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:  # its sweep runs
            os.close(fd)
            continue
        try:
            _remove_tree(path)
        finally:
            os.close(fd)


def _remove_tree(path):
    """Removes the folder `path` and what it holds, as far as it can, by paths: one descriptor at
    a time (shutil.rmtree holds one per level)."""
    try:
        names = os.listdir(path)
    except OSError:
        names = []
    for name in names:
        p = os.path.join(path, name)
        if os.path.isdir(p) and not os.path.islink(p):
            _remove_tree(p)
        else:
            try:
                os.remove(p)
            except OSError:
                pass
    try:
        os.rmdir(path)
    except OSError:
        pass


def _start_embedded(workers, client_class):
    """The embedded cluster, its client and its scratch folder (_Scratch); raises
    ClusterFailed when the cluster or the client does not start (no job ran; the scratch folder
    removed). Before, a failed start was a traceback, or an error named as the output folder's."""
    cluster, scratch = None, None
    try:
        scratch = _Scratch()
        cluster = embedded_cluster(workers, scratch.path)
        return cluster, client_class(cluster), scratch
    except BaseException as e:  # Ctrl-C during the start too: nothing left behind
        if cluster is not None:
            try:
                cluster.close()
            except Exception:
                pass
        if scratch is not None:
            scratch.remove()
        if not isinstance(e, Exception):
            raise
        hint = ""
        if _errno_of(e) in (errno.EMFILE, errno.ENFILE):
            hint = ("; it needs more open files than this process may have: raise `ulimit -n`, "
                    "or run with --shard 0/1")
        raise ClusterFailed("the embedded Dask cluster did not start ({}: {}){}".format(
            type(e).__name__, e, hint))


def _has_dashboard():
    """Dask's dashboard needs bokeh (pip's bokeh; Debian 12 does not package it)."""
    try:
        import bokeh  # noqa: F401
        return True
    except ImportError:
        return False


# Dask's background work, which shares the cores with the jobs: each worker's statistical
# profiler samples its threads every 10 ms, every event loop checks its own latency every 20 ms,
# the memory monitors run every 100 ms, the system monitors (the dashboard's CPU and memory plots)
# and the cluster's widget every 500 ms, the client asks for the scheduler's state every 2 s and
# the scheduler looks for work to steal every 100 ms, for tasks that only wait for their child
# processes. Off, or slowed, in the embedded cluster (lab/sweep/README.md); work stealing stays
# on, for the last jobs of a sweep with fewer jobs than twice the workers.
QUIET_WORKERS = {"distributed.worker.profile.enabled": False,
                 "distributed.admin.tick.interval": "1s",
                 "distributed.worker.memory.monitor-interval": "1s",
                 "distributed.admin.system-monitor.interval": "1s",
                 "distributed.deploy.cluster-repr-interval": "1h",
                 "distributed.client.scheduler-info-interval": "10s",
                 "distributed.scheduler.work-stealing-interval": "1s"}


# Evaluated on the scheduler (Client.run_on_scheduler(eval, ...)): whether it can serve the
# dashboard's pages. Its HTTP server runs without bokeh too (its link then answers 404).
_BOKEH_PROBE = "__import__('importlib.util').util.find_spec('bokeh') is not None"


def _scheduler_has_dashboard(client):
    try:
        return ("dashboard" in client.scheduler_info().get("services", {})
                and bool(client.run_on_scheduler(eval, _BOKEH_PROBE)))
    except Exception:  # an old or odd scheduler: say nothing rather than a dead link
        return False


def embedded_cluster(workers, local_directory=None):
    import dask
    from distributed import LocalCluster
    dask.config.set(QUIET_WORKERS)
    # The workers are threads of this process, one per job at a time: a job is a process of its
    # own (sweep_job), so a worker process would add no isolation, only a Python interpreter to
    # start and heartbeats over TCP (lab/sweep/README.md). No memory limit: the workers hold no
    # data (a job's memory is its process's), so nothing to monitor.
    return LocalCluster(n_workers=workers, threads_per_worker=1, processes=False, memory_limit=0,
                        # Any free port: the scheduler's HTTP server runs with or without a
                        # dashboard, and on Dask's default port (8787) it warned on every sweep
                        # while the user's own cluster held that port.
                        dashboard_address="127.0.0.1:0",
                        local_directory=local_directory, silence_logs=40)


# The client looks for the source code of the call that submits a computation (walking the
# stack, finding every frame's module: a fair part of a second, before the first job can start),
# to show it on the dashboard; the sweep's tasks have no code worth showing, so every module is
# skipped.
CLIENT_CONFIG = {"distributed.diagnostics.computations.ignore-modules": [".*"]}


# Evaluated on each worker of an existing cluster (Client.run(eval, ...), eval being importable
# everywhere): whether it can import the package, without the package on the client's side of
# the call. A worker that cannot import it would otherwise fail every task it takes up in a way
# Dask does not report to the client (the sweep would wait for ever).
_IMPORT_PROBE = "__import__('shellcontract.sweep_job').sweep_job.__file__"


def _check_workers(client, cli, version, own_cli, message):
    """Every worker of an existing cluster can import the package and finds an executable of the
    sweep's version (sweep_cli.worker_cli); raises WorkersUnusable naming each one that cannot.
    Workers that join later are checked by their first job (which then crashes, saying why)."""
    workers = sorted(client.scheduler_info().get("workers", {}))
    if not workers:
        message("the cluster has no workers yet: the jobs wait for the first to join")
        return
    problems = []
    imported = client.run(eval, _IMPORT_PROBE, workers=workers, on_error="return")
    usable = []
    for w in workers:
        r = imported.get(w)
        if isinstance(r, BaseException):
            problems.append("{}: cannot import the shellcontract package ({}: {}); every worker "
                            "needs it importable (PYTHONPATH)".format(w, type(r).__name__, r))
        else:
            usable.append(w)
    if usable:
        described = client.run(sweep_cli.describe_worker, cli, version, own_cli, workers=usable,
                               on_error="return")
        for w in usable:
            r = described.get(w)
            if isinstance(r, BaseException):
                problems.append("{}: {}: {}".format(w, type(r).__name__, r))
            elif r[1] is not None:
                problems.append("{}: {}".format(w, r[1]))
    if problems:
        raise WorkersUnusable("; ".join(problems))


def _stop_jobs(client, futures, scheduler, token):
    """Cancels the sweep's tasks and stops its running jobs (SIGTERM: each saves its checkpoint);
    returns how many still ran when the sweep gave up waiting (None: unknown)."""
    try:
        client.cancel(futures)
    except Exception:  # the scheduler or the connection is gone: the jobs are stopped below
        pass
    if scheduler:
        # A cancelled task that runs goes on in its worker's thread: the workers are asked to
        # stop this sweep's jobs.
        return _stop_on_workers(client, token)
    # The embedded workers are this process's threads: their jobs are told to stop here and
    # waited for.
    sweep_job.stop_running(token)
    return (0 if sweep_job.wait_stopped(sweep_job.STOP_GRACE_SECONDS, token)
            else sweep_job.active_calls(token))


def _stop_on_workers(client, token):
    """An existing cluster's workers stop this sweep's jobs (SIGTERM: each saves its checkpoint;
    none starts after), and the sweep waits for them; returns how many still ran when it gave up
    (None: a worker did not answer)."""
    import time
    deadline = time.monotonic() + sweep_job.STOP_GRACE_SECONDS + 5
    try:
        client.run(sweep_job.stop_running, token, on_error="return")
        while True:
            counts = client.run(sweep_job.active_calls, token, on_error="return")
            if any(isinstance(n, BaseException) for n in counts.values()):
                return None
            still = sum(counts.values())
            if still == 0 or time.monotonic() > deadline:
                return still
            time.sleep(0.2)
    except Exception:  # the scheduler or the connection is gone
        return None


def connect(args, cli, version):
    """A client of the existing cluster (--scheduler) whose workers have passed _check_workers;
    made before DIR is claimed, so that a refused cluster leaves no folder behind. Raises
    WorkersUnusable, or OSError when the scheduler does not answer."""
    import dask
    from distributed import Client
    dask.config.set(CLIENT_CONFIG)
    client = Client(args.scheduler, timeout="30s")
    try:
        # Each worker runs its own executable (unless --cli names one), of the sweep's version.
        _check_workers(client, cli, version, args.cli is None,
                       lambda text: print("shellcontract sweep: " + text, file=sys.stderr))
    except BaseException:
        client.close()
        raise
    return client


def run_jobs(todo, args, cli, version, token, progress, on_record, client=None):
    """The jobs on the existing cluster of `client` (from connect), or on an embedded one."""
    import dask
    from distributed import Client
    dask.config.set(CLIENT_CONFIG)
    cluster, threads, scratch = None, None, None
    own_cli = None if not args.scheduler else args.cli is None
    # An existing cluster's jobs take their machine's share, which each job's worker works out.
    share = (None if client is None else
             sweep_host.cluster_share(client.scheduler_info().get("workers", {}), len(todo)))
    if client is None:
        # The embedded workers run this machine's executable, on the cores this process may use.
        workers = sweep_host.embedded_workers(args.workers, len(todo))
        threads = sweep_host.job_threads(workers, len(todo))
        cluster, client, scratch = _start_embedded(workers, Client)
    futures = {}
    try:
        if _scheduler_has_dashboard(client) if args.scheduler else _has_dashboard():
            # The scheduler's own dashboard when it has one (it says where).
            progress.message("Dask dashboard: {}".format(client.dashboard_link))
        elif args.scheduler:
            progress.message("Dask dashboard: not available (the scheduler runs without one, or "
                             "without the Python package bokeh that it needs)")
        else:
            progress.message("Dask dashboard: not available (it needs the Python package bokeh, "
                             "which Debian 12 does not package)")
        progress.restart_clock()  # the ETA counts from the cluster's start, not its set-up
        # Finished futures are handed over through a queue that this thread blocks on:
        # distributed's as_completed looks for them every 100 ms.
        finished = queue.SimpleQueue()
        # One call for all the jobs: one graph for the scheduler, not one per job.
        submitted = client.map(sweep_job.run_job, [job.to_dict() for job in todo],
                               out_dir=args.output, cli=cli, timeout=args.job_timeout,
                               checkpoint_every=args.checkpoint_every, sweep=token,
                               own_cli=own_cli, version=version, threads=threads,
                               share=share, lock_wait=args.lock_wait, pure=False,
                               # This sweep's own keys: two sweeps on one cluster with the
                               # same job (its id is the run's, not the folder's) had shared one
                               # task, whose files went to the first sweep's folder only.
                               key=["shellcontract-job-{}-{}".format(job.id, token)
                                    for job in todo])
        for f, job in zip(submitted, todo):
            futures[f] = job
            f.add_done_callback(finished.put)
        for _ in range(len(futures)):
            f = sweep_progress.next_finished(finished, client, args.scheduler, progress,
                                             args.note_every)
            job = futures[f]
            try:
                record = f.result()
            except Exception as e:  # the task itself failed (e.g. a worker lost too often)
                record = {"job": job.id, "status": "crashed", "exit_code": None,
                          "message": "{}: {}".format(type(e).__name__, e)}
            on_record(job, record)
    except BaseException as e:
        # Ctrl-C, or any error that ends the sweep here (the results tables unwritable, the
        # scheduler gone): the jobs are stopped, not left running behind a sweep that has ended.
        still = _stop_jobs(client, list(futures), args.scheduler, token)
        if isinstance(e, KeyboardInterrupt):
            raise Interrupted(still)
        if not isinstance(e, Exception):
            raise
        raise JobsStopped(e, still) from e
    finally:
        if cluster is not None:  # an existing cluster's client is its caller's to close
            try:
                client.close()
                cluster.close()
            finally:
                scratch.remove()  # after the close, which gives the descriptors back
