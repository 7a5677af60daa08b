"""python3 -m shellcontract.sweep SWEEP.json -o DIR: many contraction runs, on Dask distributed.

Every job of the sweep file is validated before any runs; then the jobs run on an embedded local
cluster (one worker per core it may use, a thread of this process that waits for its job's
process; the jobs at once share those cores), on an existing cluster (--scheduler
tcp://HOST:PORT), or one slice of them serially (--shard I/N, for Slurm or Kubernetes job arrays).
Each job is `shellcontract run` in a process of its own; its outcome lands whole in
DIR/jobs/<id>/ and a row of DIR/results.csv and results.json. Running the same file again skips
the finished jobs.
docs/design/sweeps.md says how and why.

Exit codes: 0 every job ran (whatever its outcome: see the results' status column), 1 bad usage,
or a refused sweep file, output folder or cluster (nothing run), or an output folder that cannot
be written before any job started, 3 some job could not get an outcome (crash, kill, timeout, an
output not written, its checkpoint not read, a resource the system refused; also memory or open
files short while the meshes are checked: nothing run) or runs in another sweep, or an error stopped the sweep after its jobs started (the tables or DIR not writable: the
jobs' outcomes are kept), 130 interrupted (run the same command again to finish).
"""

import argparse
import errno
import os
import shlex
import subprocess
import sys
import uuid

from . import (number_text, sweep_checkpoint, sweep_cli, sweep_dask, sweep_file, sweep_host,
               sweep_job, sweep_output, sweep_process, sweep_progress, sweep_results)

EXIT_USAGE = 1
EXIT_INCOMPLETE = 3
EXIT_INTERRUPTED = 130
# Jobs whose outcome is not a result the same run would give again.
RETRIED_STATUSES = ("crashed", "killed", "timeout", sweep_job.OUTPUT_NOT_WRITTEN,
                    sweep_job.OUT_OF_RESOURCES, sweep_job.CHECKPOINT_NOT_READ)


find_cli = sweep_cli.find_cli
cli_version = sweep_cli.cli_version


def parse_shard(text):
    i, n = (number_text.integer(x) for x in text.split("/", 1)) if "/" in text else (None, None)
    if i is None or n is None:
        raise argparse.ArgumentTypeError("expected I/N, e.g. 0/4, got {!r}".format(text))
    if n < 1 or not 0 <= i < n:
        raise argparse.ArgumentTypeError("expected 0 <= I < N, got {!r}".format(text))
    return i, n


# The longest --job-timeout (sweep_job.MAX_SECONDS: far beyond any job, within what the waits
# can take).
MAX_JOB_TIMEOUT = sweep_job.MAX_SECONDS
# --checkpoint-every goes to `shellcontract run`, which takes an int.
MAX_CHECKPOINT_EVERY = 2**31 - 1
# The most workers of the embedded cluster (sweep_host.MAX_WORKERS).
MAX_WORKERS = sweep_host.MAX_WORKERS


# The numbers are read in the tool's grammar (number_text), not by Python's int() and float().
def job_timeout(text):
    v = number_text.decimal(text)
    if v is None or not 0 < v <= MAX_JOB_TIMEOUT:
        raise argparse.ArgumentTypeError(
            "expected a number of seconds > 0 and <= {:g}, got {!r}".format(MAX_JOB_TIMEOUT, text))
    return v


def positive_int(text, most=None):
    v = number_text.integer(text)
    if v is None or v < 1 or (most is not None and v > most):
        raise argparse.ArgumentTypeError("expected an integer >= 1{}, got {!r}".format(
            "" if most is None else " and <= {}".format(most), text))
    return v


def checkpoint_every(text):
    return positive_int(text, MAX_CHECKPOINT_EVERY)


def workers(text):
    return positive_int(text, MAX_WORKERS)


class _Once(argparse.Action):
    """An option given once, as the C++ commands take each (argparse's own keeps the last of
    `--workers 2 --workers 3`); a switch with nargs=0."""

    def __init__(self, option_strings, dest, nargs=None, **kwargs):
        self._switch = nargs == 0
        super().__init__(option_strings, dest, nargs=nargs, **kwargs)

    def __call__(self, parser, namespace, values, option_string=None):
        given = namespace.__dict__.setdefault("_given", set())
        if self.dest in given:
            parser.error("option '{}' cannot be given more than once".format(
                max(self.option_strings, key=len)))
        given.add(self.dest)
        setattr(namespace, self.dest, True if self._switch else values)


class _Parser(argparse.ArgumentParser):
    """Bad usage exits 1, as the tool's other commands do (argparse's own is 2, which is the
    tool's 'unusable input')."""

    def error(self, message):
        self.print_usage(sys.stderr)
        self.exit(EXIT_USAGE, "{}: error: {}\n".format(self.prog, message))

    def print_help(self, file=None):
        # --help is stdout's product, checked as every command's is (write_stdout); argparse's
        # own dropped it silently when stdout was closed (exit 0) and left a full one to the
        # interpreter's exit, a traceback.
        if file is None:
            write_stdout(self.format_help())
        else:
            super().print_help(file)


class StdoutUnwritable(Exception):
    """What the sweep prints on stdout (--help, --dry-run's list) could not be written; the
    message says why."""


def write_stdout(text):
    """`text` on stdout, flushed; raises StdoutUnwritable when stdout is closed or the write
    fails (a full disk, a reader gone). Then stdout's descriptor is /dev/null, so that the
    interpreter's flush at exit does not fail again (a traceback, exit 120)."""
    if sys.stdout is None:  # Python's stdout when fd 1 was closed
        raise StdoutUnwritable("it is closed")
    try:
        sys.stdout.write(text)
        sys.stdout.flush()
    except (OSError, ValueError) as e:
        sweep_process.point_at_devnull(sys.stdout)
        raise StdoutUnwritable(getattr(e, "strerror", None) or str(e))


# The options that take a value: `-o -dir` gives that value as the C++ commands take `-o -x.off`
# (argparse reads a word that starts with '-' as an option and refused it: "expected one
# argument").
VALUE_OPTIONS = ("-o", "--output", "--scheduler", "--shard", "--workers", "--job-timeout",
                 "--checkpoint-every", "--cli")
OPTION_WORDS = VALUE_OPTIONS + ("-h", "--help", "--dry-run")


def joined_values(argv):
    """`argv` with each value option followed by a word that starts with one '-' (and is no
    option of the sweep's) joined to it as `--option=VALUE`, up to a `--`."""
    out, i = [], 0
    while i < len(argv):
        word = argv[i]
        if word == "--":
            return out + argv[i:]
        nxt = argv[i + 1] if i + 1 < len(argv) else None
        if (word in VALUE_OPTIONS and nxt is not None and nxt.startswith("-") and nxt != "-"
                and not nxt.startswith("--") and nxt not in OPTION_WORDS):
            long = "--output" if word == "-o" else word
            out.append("{}={}".format(long, nxt))
            i += 2
            continue
        out.append(word)
        i += 1
    return out


def parser():
    p = _Parser(
        prog="shellcontract sweep",
        # Options are named in full, as the tool's other commands take theirs (docs/cli.md): a
        # prefix a script relies on would break when an option is added.
        allow_abbrev=False,
        description="Run every job of a sweep file (meshes x options grid x runs) on Dask "
                    "distributed; results in DIR/results.csv and DIR/jobs/<id>/.",
        epilog="exit codes: 0 every job has an outcome (see the status column), 1 bad usage or a "
               "refused sweep file, output folder or cluster (nothing run), 3 some job crashed, "
               "was killed, timed out, could not write its output, read its checkpoint or have "
               "a resource the system refused (also while the meshes were checked: nothing "
               "run), or runs in another sweep, or an error (the "
               "results tables or DIR not writable) stopped the sweep after its jobs started: "
               "the finished jobs' outcomes are kept, 130 interrupted (run the same command "
               "again to finish)")
    p.add_argument("sweep", metavar="SWEEP.json")
    p.add_argument("-o", "--output", metavar="DIR", required=True, action=_Once,
                   help="results folder: new, empty, or this sweep file's from an earlier sweep")
    where = p.add_mutually_exclusive_group()
    where.add_argument("--scheduler", metavar="tcp://HOST:PORT", action=_Once,
                       help="an existing Dask cluster (dask scheduler / dask worker); DIR and the "
                            "meshes must be at the same paths on every worker")
    where.add_argument("--shard", metavar="I/N", type=parse_shard, action=_Once,
                       help="run only the I-th of N slices of the jobs, serially in this process "
                            "(job arrays: Slurm, Kubernetes indexed jobs)")
    p.add_argument("--workers", type=workers, default=None, action=_Once,
                   help="jobs at a time on the embedded cluster, at most {} (default: the cores "
                        "this process may use, at most {}); no more workers start than there are "
                        "jobs to run; not with --scheduler or --shard, which start no embedded "
                        "cluster".format(MAX_WORKERS, MAX_WORKERS))
    p.add_argument("--job-timeout", type=job_timeout, default=None, metavar="SECONDS", action=_Once,
                   help="stop a job after this long (recorded as 'timeout'; a later sweep "
                        "resumes it from its checkpoint)")
    p.add_argument("--checkpoint-every", type=checkpoint_every, default=20, metavar="N",
                   action=_Once,
                   help="each job saves its state every N frames (a lost worker's job resumes "
                        "from there); default 20")
    p.add_argument("--cli", metavar="PATH", action=_Once,
                   help="the shellcontract executable (default: $SHELLCONTRACT_CLI, the build "
                        "tree, PATH; with --scheduler each worker finds its own unless this is "
                        "given)")
    p.add_argument("--dry-run", action=_Once, nargs=0, default=False,
                   help="validate the sweep file and list the jobs; run nothing")
    return p


def scheduler_address_problem(address):
    """Why `address` is no scheduler's address (Dask's parse, then what it lets through: a port
    out of [1, 65535], or written otherwise than the tool's integers, " 8786" or "8_786"; a blank
    anywhere), or None."""
    from distributed.comm.addressing import parse_address, parse_host_port
    try:
        parse_host_port(parse_address(address)[1])
    except ValueError as e:
        return str(e)
    if any(c.isspace() for c in address):
        return "it has a blank"
    port = address.rsplit(":", 1)[1]
    if not ("0" <= port[:1] <= "9" and 1 <= (number_text.integer(port) or 0) <= 65535):
        return "the port must be an integer in [1, 65535], got {!r}".format(port)
    return None


def _os_error_text(e):
    where = e.filename if e.filename is not None else ""
    return "{}{}".format(where + ": " if where else "", e.strerror or e)


def main(argv=None, *, lock_wait=sweep_job.JOB_LOCK_WAIT_SECONDS,
         note_every=sweep_progress.WAIT_NOTE_SECONDS):
    """The sweep of the command line `argv` (None: sys.argv[1:]); returns its exit code.

    Two timings that the command line does not take (docs/design/sweeps.md, "Jobs" and "Where
    the jobs run"), each a number of seconds, a ValueError naming it otherwise: `lock_wait`
    (>= 0), how long an attempt of a job waits for another attempt that holds the job's lock
    before it leaves the job `running elsewhere`; it goes with each job to its worker.
    `note_every` (> 0), how often a sweep on a cluster without workers says so again."""
    lock_wait = sweep_job.seconds("lock_wait", lock_wait)
    note_every = sweep_job.seconds("note_every", note_every, zero=False)
    with sweep_process.stop_signals_as_ctrl_c():
        try:
            return _main(argv, lock_wait, note_every)
        except StdoutUnwritable as e:
            print("shellcontract sweep: cannot write to standard output: {} (what it printed is "
                  "incomplete)".format(e), file=sys.stderr)
            return EXIT_USAGE
        except KeyboardInterrupt:
            # Outside the running of the jobs (which says more): while checking the executable,
            # reading the sweep file or claiming DIR, whose writes are whole or absent. An
            # uncaught KeyboardInterrupt would end the process by SIGINT, after a traceback.
            print("shellcontract sweep: interrupted; run the same command again",
                  file=sys.stderr)
            return EXIT_INTERRUPTED


def _main(argv, lock_wait, note_every):
    sweep_host.guard_stderr()
    command_line = parser()
    args = command_line.parse_args(joined_values(sys.argv[1:] if argv is None else list(argv)))
    # --workers is the embedded cluster's: with either of these no embedded cluster starts, and
    # it had been dropped without a word (a user who gave it believed it limited something).
    if args.workers is not None and args.scheduler is not None:
        command_line.error("argument --workers: not with --scheduler (the cluster's own workers "
                           "run the jobs, as many at once as their threads: start as many as you "
                           "want with `dask worker --nworkers N --nthreads 1`)")
    if args.workers is not None and args.shard is not None:
        command_line.error("argument --workers: not with --shard (a shard runs its jobs one at a "
                           "time in this process: run more shards at once for more jobs at once)")
    # With the per-sweep settings of the command line, which reach each job the same way.
    args.lock_wait, args.note_every = lock_wait, note_every
    cli = find_cli(args.cli)
    if cli is None:  # a path named by --cli or $SHELLCONTRACT_CLI is never replaced by another
        print("shellcontract sweep: " + sweep_cli.not_found(args.cli), file=sys.stderr)
        return EXIT_USAGE
    try:
        version = cli_version(cli)
    except (OSError, subprocess.SubprocessError) as e:
        print("shellcontract sweep: {} --version failed ({})".format(cli, e), file=sys.stderr)
        return EXIT_USAGE
    # Any executable answers --version somehow (/bin/true with nothing): one that is not the
    # tool would have its jobs recorded as ok without a result.
    if not version.startswith("shellcontract "):
        print("shellcontract sweep: {} is not the shellcontract executable (its --version printed "
              "{!r})".format(cli, version), file=sys.stderr)
        return EXIT_USAGE
    if not args.output:
        print("shellcontract sweep: -o: empty; give the output folder", file=sys.stderr)
        return EXIT_USAGE
    if args.scheduler is not None:
        # Checked before DIR is claimed (a traceback from the client before: 'bogus').
        why = scheduler_address_problem(args.scheduler)
        if why:
            print("shellcontract sweep: refused, nothing run: --scheduler {!r} is not an address "
                  "tcp://HOST:PORT ({})".format(args.scheduler, why), file=sys.stderr)
            return EXIT_USAGE
    args.output = os.path.abspath(args.output)
    try:
        data = sweep_file.load(args.sweep)
        jobs = sweep_file.expand(args.sweep, data, version)
        # Before anything is written or run: what the sweep writes in DIR, against what it reads.
        args.inputs = sweep_file.inputs(args.sweep, jobs)
        sweep_output.check(args.output, args.sweep, args.inputs, [j.id for j in jobs])
    except (sweep_file.SweepError, sweep_output.OutputError) as e:
        print("shellcontract sweep: refused, nothing run: {}".format(e), file=sys.stderr)
        return EXIT_USAGE
    except sweep_file.ResourceShort as e:
        print("shellcontract sweep: nothing run, the system refused a resource while a mesh was "
              "checked (the sweep file is not at fault): {}".format(e), file=sys.stderr)
        return EXIT_INCOMPLETE
    try:
        return _run(args, cli, version, data, jobs)
    except sweep_output.OutputError as e:
        print("shellcontract sweep: refused, nothing run: {}".format(e), file=sys.stderr)
        return EXIT_USAGE
    except sweep_dask.ClusterFailed as e:
        print("shellcontract sweep: nothing run: {}".format(e), file=sys.stderr)
        return EXIT_USAGE
    except OSError as e:  # DIR unwritable, full, changed under the sweep (finished jobs stay)
        hint = ""
        if e.errno in (errno.EMFILE, errno.ENFILE):
            hint = (" (the sweep and its cluster need more open files than this process may "
                    "have: raise `ulimit -n`, or run with --shard 0/1)")
        print("shellcontract sweep: {}: {}{}".format(args.output, _os_error_text(e), hint),
              file=sys.stderr)
        return EXIT_USAGE


def _run(args, cli, version, data, jobs):
    varying = sweep_file.varying_names(data)
    sweep_dir = os.path.dirname(os.path.abspath(args.sweep))
    selected = jobs if args.shard is None else jobs[args.shard[0]::args.shard[1]]
    if args.dry_run:
        # The mesh and `run`'s arguments quoted for a shell ('0:1, 60:0.5' is one argument);
        # with --shard, that shard's jobs only.
        write_stdout("".join(
            "{}  {}  {}\n".format(job.id, shlex.quote(os.path.relpath(job.mesh, sweep_dir)),
                                  " ".join(shlex.quote(a) for a in job.args))
            for job in selected))
        return 0
    client = None
    if args.scheduler:
        try:
            client = sweep_dask.connect(args, cli, version)
        except sweep_dask.WorkersUnusable as e:
            print("shellcontract sweep: refused, nothing run: {}".format(e), file=sys.stderr)
            return EXIT_USAGE
        except KeyboardInterrupt:  # while connecting (up to 30 s) or checking the workers
            print("shellcontract sweep: interrupted before anything ran", file=sys.stderr)
            return EXIT_INTERRUPTED
    try:
        return _claim_and_run(args, cli, version, jobs, selected, varying, sweep_dir, client)
    finally:
        if client is not None:
            client.close()


def _stopped_by_error(args, e):
    """The exit code and message of a sweep ended by an error once its jobs had started (the
    results tables not writable, DIR full, the scheduler gone): the finished jobs' outcomes are
    in DIR/jobs, the running jobs were stopped (each saved its checkpoint), and the same command
    finishes the sweep and rewrites the tables. Not the 1 of a sweep refused before it ran."""
    still = 0
    if isinstance(e, sweep_dask.JobsStopped):
        still = e.still_running
        if not isinstance(e.error, OSError):  # not the machine's: a traceback, as before
            raise e.error
        e = e.error
    hint = ""
    if e.errno in (errno.EMFILE, errno.ENFILE):
        hint = (" (the sweep and its cluster need more open files than this process may have: "
                "raise `ulimit -n`, or run with --shard 0/1)")
    if still == 0:
        how = "any job still running was stopped and saved its checkpoint"
    else:
        which = "some jobs" if still is None else "{} job{}".format(still, "s" * (still > 1))
        how = "{} did not stop in time and may still run: their outcomes are kept".format(which)
    print("shellcontract sweep: stopped after its jobs started: {}{}; the finished jobs' "
          "outcomes are kept in {}, {}; run the same command again to finish (it rewrites "
          "results.csv and results.json)".format(_os_error_text(e), hint,
                                                 os.path.join(args.output, "jobs"), how),
          file=sys.stderr)
    return EXIT_INCOMPLETE


def _claim_and_run(args, cli, version, jobs, selected, varying, sweep_dir, client):
    sweep_output.claim(args.output, args.sweep, args.inputs, [j.id for j in jobs])
    # Before this sweep writes its own: those of a sweep killed (SIGKILL) while writing a table.
    stale_tables = sweep_output.remove_stale_temporaries(args.output)
    tables = sweep_results.Writer(jobs, varying, args.output, sweep_dir)
    todo = [j for j in selected if not sweep_job.is_done(tables.records[j.id])]
    sweep_results.write(jobs, varying, args.output, sweep_dir, records=tables.records)
    done = len(selected) - len(todo)
    # The progress counts finished jobs as the final summary does: a result (ok, target not
    # reached) is done, any other final outcome (failed, bad input, ...) failed.
    running = {j.id for j in todo}
    earlier = [tables.records[j.id]["status"] for j in selected if j.id not in running]
    results_before = sum(1 for status in earlier if status in sweep_progress.RESULT_STATUSES)
    progress = sweep_progress.Progress(len(selected), done=results_before,
                                       failed=done - results_before)
    progress.message("{} jobs ({} in this run, {} done already) -> {}".format(
        len(jobs), len(todo), done, args.output))
    stale = sweep_job.clean_stale_attempts(args.output)
    sweep_checkpoint.remove_done(args.output, [j.id for j in selected if j.id not in running])
    if stale:
        progress.message("removed the working folders of {} attempt{} that a killed sweep left in "
                         "{}".format(stale, "s" * (stale > 1), os.path.join(args.output, ".work")))
    if stale_tables:
        progress.message("removed {} temporary file{} of the results tables that a killed sweep "
                         "left in {}".format(stale_tables, "s" * (stale_tables > 1), args.output))

    def on_record(job, record):
        tables.record(job, record)
        progress.job_finished(record, job.label())

    token = uuid.uuid4().hex  # this sweep's jobs, for stopping them (sweep_job.stop_running)
    try:
        if args.shard is not None:
            for job in todo:
                on_record(job, sweep_job.run_job(job.to_dict(), args.output, cli, args.job_timeout,
                                                 args.checkpoint_every, sweep=token,
                                                 lock_wait=args.lock_wait))
        elif todo:  # nothing left to run: no cluster to start
            sweep_dask.run_jobs(todo, args, cli, version, token, progress, on_record, client)
        table = tables.flush()
    except (KeyboardInterrupt, sweep_dask.Interrupted) as e:
        try:
            tables.flush()
        except OSError as error:  # the tables are rewritten by the next sweep
            print("shellcontract sweep: {}: the results tables could not be rewritten: {}".format(
                args.output, _os_error_text(error)), file=sys.stderr)
        progress.close()
        still = e.still_running if isinstance(e, sweep_dask.Interrupted) else 0
        if still == 0:
            how = ("finished jobs are kept, the running ones saved their checkpoints and resume "
                   "from them")
        else:
            which = "some jobs" if still is None else "{} job{}".format(still, "s" * (still > 1))
            how = ("finished jobs are kept; {} did not stop in time and may still run on the "
                   "workers: their outcomes are kept when they end".format(which))
        print("shellcontract sweep: interrupted; run the same command again to finish the rest "
              "({})".format(how), file=sys.stderr)
        return EXIT_INTERRUPTED
    except (OSError, sweep_dask.JobsStopped) as e:
        progress.close()
        return _stopped_by_error(args, e)
    progress.close()
    ids = {j.id for j in selected}
    incomplete = [r for r in table if r["job"] in ids and
                  (r["status"] in RETRIED_STATUSES + ("pending", "interrupted",
                                                      sweep_job.RUNNING_ELSEWHERE))]
    done, failed, left = sweep_results.counts([r for r in table if r["job"] in ids])
    # Left to another attempt and not finished by it (the table may show an earlier outcome that
    # is not final, a crash, rather than this sweep's attempt).
    elsewhere = sum(1 for r in table if r["job"] in ids
                    and (tables.latest.get(r["job"]) or {}).get("status")
                    == sweep_job.RUNNING_ELSEWHERE
                    and r["status"] not in sweep_job.FINAL_STATUSES)
    if elsewhere:
        print("shellcontract sweep: {} job{} left running in another sweep or worker (its "
              "outcome is kept when it ends); run the same command again then to see {}".format(
                  elsewhere, "s" * (elsewhere > 1), "them" if elsewhere > 1 else "it"),
              file=sys.stderr)
    print("shellcontract sweep: {} done, {} failed, {} left; results in {}".format(
        done, failed, left, os.path.join(args.output, "results.csv")), file=sys.stderr)
    return EXIT_INCOMPLETE if incomplete else 0


if __name__ == "__main__":
    sys.exit(main())
