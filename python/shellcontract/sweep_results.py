"""DIR/results.csv and DIR/results.json: one row per job of the sweep file, in the file's order,
from the jobs' records (DIR/jobs/<id>/job.json); a job without one is "pending". Both files are
written whole and renamed, so a reader never sees half a table."""

import csv
import decimal
import io
import json
import math
import os
import time

from . import sweep_file, sweep_job, sweep_output, sweep_progress

RESULT_COLUMNS = ("status", "exit_code", "final_volume_ratio", "frames_run", "wall_seconds",
                  "resumed", "peak_memory_mb", "new_intersections", "output")


def columns(varying):
    return ["job", "mesh"] + list(varying) + list(RESULT_COLUMNS)


def rows(jobs, varying, out_dir, sweep_dir, latest=None, records=None):
    """The table's rows (dicts); `latest` maps job id -> a record newer than the folder's (an
    interrupted attempt, which has no folder). `records` (job id -> record or None) stands for
    the job folders when given: a sweep reads each folder once, not every job's after each."""
    latest = latest or {}
    out = []
    for job in jobs:
        if records is not None:
            record = records.get(job.id)
        else:
            record = sweep_job.read_record(out_dir, job.id)
        record = record or latest.get(job.id)
        row = {"job": job.id, "mesh": os.path.relpath(job.mesh, sweep_dir)}
        for name in varying:
            row[name] = job.varying.get(name, job.options.get(name, ""))
        # A result not there is None: null in results.json, as in the job's job.json (it had
        # been "", a string in a column of numbers), and an empty cell in results.csv.
        if record is None:
            row.update({k: None for k in RESULT_COLUMNS})
            row["status"] = "pending"
        else:
            for k in RESULT_COLUMNS:
                row[k] = record.get(k)
        out.append(row)
    return out


def shortest_text(x):
    """A float as the tool writes numbers (C++'s std::to_chars: the fewest digits that read back
    as the same double, fixed or scientific notation whichever is shorter, fixed on a tie), so
    that a cell reads like the tool's own text of the value (its --summary, its resolved
    options): 1e6 is 1e+06, 250000.0 is 250000, 0.0001 is 1e-04."""
    if math.isnan(x):
        return "nan"
    if math.isinf(x):
        return "inf" if x > 0 else "-inf"
    sign = "-" if math.copysign(1.0, x) < 0 else ""
    if x == 0:
        return sign + "0"
    _, digits, exp = decimal.Decimal(repr(abs(x))).as_tuple()  # repr: the fewest digits
    digits = list(digits)
    while len(digits) > 1 and digits[-1] == 0:
        digits.pop()
        exp += 1
    ds = "".join(str(d) for d in digits)
    n = len(ds)
    if exp >= 0:  # an integer: printf's %.0f, the double's exact value (past 2^53, more digits)
        fixed = str(int(abs(x)))
    elif n + exp > 0:
        fixed = ds[:n + exp] + "." + ds[n + exp:]
    else:
        fixed = "0." + "0" * -(n + exp) + ds
    e = exp + n - 1
    scientific = "{}{}e{}{:02d}".format(ds[0], "." + ds[1:] if n > 1 else "", "-" if e < 0 else "+",
                                        abs(e))
    return sign + (fixed if len(fixed) <= len(scientific) else scientific)


def _cell(v):
    if v is None:
        return ""
    if isinstance(v, bool):
        return "on" if v else "off"
    if isinstance(v, float):
        return shortest_text(v)
    if isinstance(v, (list, tuple)):
        # Points of region_at, [[x, y, z], ...]: the CLI's text, 'X,Y,Z;X,Y,Z', so that the cell
        # tells the points apart.
        sep = ";" if any(isinstance(x, (list, tuple)) for x in v) else ","
        return sep.join(_cell(x) for x in v)
    return str(v)


def _option_cell(job, name, value):
    """An option's cell: the tool's own text of the value (its resolved options), so that an
    integer in the file (1000000) reads as the same number given as a float (1e+06) does, and a
    keyframe list as the CLI's '0:1, 60:0.5'. A file option keeps the file's text (its resolved
    text is the absolute path), and an option the job does not give stays empty."""
    if value == "" or name in sweep_file.PATH_OPTIONS:
        return _cell(value)
    return job.resolved.get(name, _cell(value))


def write(jobs, varying, out_dir, sweep_dir, latest=None, records=None):
    """Writes both files; returns the rows."""
    table = rows(jobs, varying, out_dir, sweep_dir, latest, records)
    names = columns(varying)
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(names)
    for job, row in zip(jobs, table):
        w.writerow([_option_cell(job, n, row[n]) if n in varying else _cell(row[n])
                    for n in names])
    os.makedirs(out_dir, exist_ok=True)
    sweep_output.write_atomic(os.path.join(out_dir, "results.csv"), buf.getvalue())
    sweep_output.write_atomic(os.path.join(out_dir, "results.json"),
            json.dumps([{n: row[n] for n in names} for row in table], indent=1) + "\n")
    return table


def counts(table):
    """(done, failed, left): done = an outcome the same run would give again that is a result
    (ok or target not reached); failed = any other recorded outcome; left = pending, or running
    in another sweep."""
    done = sum(1 for r in table if r["status"] in sweep_progress.RESULT_STATUSES)
    left = sum(1 for r in table if r["status"] in sweep_progress.NOT_OUTCOMES)
    return done, len(table) - done - left, left


class Writer:
    """The tables rewritten while a sweep runs: from the records it holds (each job folder read
    once), and at most once per INTERVAL_SECONDS and never more often than INTERVAL_COST times
    the last write's duration, so that a sweep of many short jobs does not spend its time
    rewriting a large table; the last write (flush) reads every folder again (another shard's
    jobs may have finished meanwhile)."""
    INTERVAL_SECONDS = 1.0
    INTERVAL_COST = 20.0

    def __init__(self, jobs, varying, out_dir, sweep_dir, clock=time.monotonic):
        self.jobs, self.varying, self.out_dir, self.sweep_dir = jobs, varying, out_dir, sweep_dir
        self.records = {j.id: sweep_job.read_record(out_dir, j.id) for j in jobs}
        self.latest = {}
        self.clock = clock
        self.next_write = clock()

    def record(self, job, record):
        """A job's new outcome; rewrites the tables when due."""
        self.latest[job.id] = record
        self.records[job.id] = sweep_job.read_record(self.out_dir, job.id) or record
        now = self.clock()
        if now >= self.next_write:
            write(self.jobs, self.varying, self.out_dir, self.sweep_dir, records=self.records)
            took = self.clock() - now
            self.next_write = now + max(self.INTERVAL_SECONDS, self.INTERVAL_COST * took)

    def flush(self):
        """Rewrites the tables from the job folders; returns the rows."""
        return write(self.jobs, self.varying, self.out_dir, self.sweep_dir, self.latest)
