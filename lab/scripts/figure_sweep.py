"""The paper figures' simulations through the sweep engine (python3 -m shellcontract.sweep, on
Dask): lab/scripts/paper_figures.py asks for runs one by one, as a figure needs them; this runner
collects those requests first, runs them as sweeps (all the cores, every job's outcome kept in
WORK/sweep/jobs/<job id>/), and then hands each figure its run.

How the requests are collected: the figures are drawn once in a collecting pass, where every run
returns a stand-in result (a summary and a log of made-up values, the input mesh) and nothing is
rendered; a figure that trips over a stand-in stops there, and the next pass (after its runs have
been made) goes further. When a pass asks for nothing new, the figures are drawn for real.

The job ids are the sweep's own (the mesh's bytes, the resolved options, the tool's version), so a
second invocation with the same --work folder skips every finished run.
"""
import json
import os
import subprocess
import sys
import tempfile
import time

import numpy as np

import mesh_measures as mm


def paper_args(args):
    """The paper's model, which its figures show, added to a run's CLI arguments where a figure
    does not set it: its PBD solver with its sequential Gauss-Seidel order, a constant pressure
    (P = 2) and the flat-rest isometric bending. The tool's defaults differ (an XPBD shell material with air inside, dihedral bending:
    docs/design/defaults.md). The paper's local contraction is its region pressure (--inward
    force), here P_A = 3 (--region-shrink 0.3, the strength the figures were made with); the
    tool's default sinks the regions as dimples instead (docs/math/local-contraction.md)."""
    args = [str(a) for a in args]
    for option, value in (("--solver", "pbd"), ("--order", "sequential"), ("--air-balance", "0"),
                          ("--bending", "isometric"), ("--pressure", "2")):
        if option not in args:
            args += [option, value]
    if any(a in args for a in ("--regions", "--aniso")) and "--inward" not in args:
        args += ["--inward", "force"]
        if "--region-shrink" not in args:
            args += ["--region-shrink", "0.3"]
    return args


def _is_value(token):
    if not token.startswith("--"):
        return True
    try:  # a negative number is a value, not a flag
        float(token)
        return True
    except ValueError:
        return False


def to_options(args):
    """CLI arguments ("--k-b", "0.1", "--measure-regions") -> the sweep's option names and
    values ({"k_b": "0.1", "measure_regions": True}); a flag without a value is a switch."""
    out, i = {}, 0
    while i < len(args):
        flag = args[i]
        if not flag.startswith("--"):
            raise ValueError(f"expected an option, got {flag!r} in {args}")
        name = flag[2:].replace("-", "_")
        if i + 1 < len(args) and _is_value(args[i + 1]):
            out[name], i = args[i + 1], i + 2
        else:
            out[name], i = True, i + 1
    return out


class _StandInSummary(dict):
    """A run's summary in the collecting pass: made-up numbers for whatever a figure reads."""

    def __missing__(self, key):
        return _StandInOptions() if key == "options" else 0.5


class _StandInOptions(dict):
    def __missing__(self, key):
        return "0"


class _StandInLog(dict):
    def __missing__(self, key):
        return np.linspace(1.0, 0.5, 3)


class SweepRunner:
    """Runs `shellcontract run` jobs through the sweep engine into WORK/sweep (the interface of
    the figures' runner: run(name, mesh, *args) -> {"summary", "log", "mesh", "args"})."""

    def __init__(self, tool, work, workers=None):
        self.tool, self.work, self.workers = os.path.abspath(tool), work, workers
        self.sweep_dir = os.path.join(work, "sweep")
        self.python_dir = os.path.join(os.path.dirname(self.tool), "python")
        sys.path.insert(0, self.python_dir)
        from shellcontract import sweep, sweep_file  # the build tree's package
        self._sweep_file = sweep_file
        self.version = sweep.cli_version(self.tool)
        self.collecting, self.pending = False, {}
        self.seconds, self.count, self.used, self.not_ok = 0.0, 0, set(), []
        self.sweeps, self.sweep_seconds = 0, 0.0

    # -------------------------------------------------------------------- the figures' call
    def run(self, name, mesh, *args):
        args = paper_args(args)
        options = dict(to_options(args), threads=1)  # one thread per job, one job per core
        mesh = os.path.abspath(mesh)
        job_id = self._job_id(mesh, options)
        record = self._record(job_id)
        if self.collecting:
            if record is None:
                self.pending[job_id] = (mesh, options)
            return {"summary": _StandInSummary(status="ok"), "log": _StandInLog(), "mesh": mesh,
                    "args": args}
        if record is None:
            raise RuntimeError(f"{name}: the sweep has no outcome for job {job_id} "
                               f"({os.path.basename(mesh)} {' '.join(args)})")
        folder = os.path.join(self.sweep_dir, "jobs", job_id)
        summary_path = os.path.join(folder, "summary.json")
        if not os.path.exists(summary_path):  # exit 1 or 2: no summary; the figures need one
            raise RuntimeError(f"{name}: job {job_id} ended '{record['status']}' without a "
                               f"summary: {record.get('message', '')}")
        with open(summary_path) as f:
            summary = json.load(f)
        if job_id not in self.used:
            self.used.add(job_id)
            self.seconds += float(record.get("wall_seconds") or 0.0)
            if summary["status"] != "ok":
                self.not_ok.append(f"{name} ({summary['status']}: {summary.get('failure', '')})")
        self.count = len(self.used)
        print(f"  {name}: V/V0 {summary['final_volume_ratio']:.4f} ({summary['status']})",
              flush=True)
        ext = os.path.splitext(mesh)[1].lower() or ".off"
        out_mesh = os.path.join(folder, os.path.splitext(os.path.basename(mesh))[0] + ext)
        return {"summary": summary, "log": mm.read_log(os.path.join(folder, "log.csv")),
                "mesh": out_mesh, "args": args}

    # -------------------------------------------------------------------- the passes
    def draw_all(self, figures, out, stand_ins):
        """figures: callables f(out) -> page section. stand_ins: {module: {name: stub}} patched
        in during the collecting passes (the renderers). Returns the sections of the real pass."""
        passes = 0
        while True:
            passes += 1
            self.collecting, self.pending = True, {}
            saved = {(m, n): getattr(m, n) for m, stubs in stand_ins.items() for n in stubs}
            for m, stubs in stand_ins.items():
                for n, stub in stubs.items():
                    setattr(m, n, stub)
            try:
                with tempfile.TemporaryDirectory() as scratch:
                    for figure in figures:
                        try:
                            figure(scratch)
                        except Exception:  # a stand-in value it cannot use: the next pass
                            pass
            finally:
                for (m, n), v in saved.items():
                    setattr(m, n, v)
                self.collecting = False
            if not self.pending:
                break
            print(f"pass {passes}: {len(self.pending)} runs to make", flush=True)
            self._run_pending()
        return [figure(out) for figure in figures]

    def _run_pending(self):
        """One sweep file per input mesh (a sweep crosses its meshes with its runs), each run on
        the embedded Dask cluster."""
        by_mesh = {}
        for mesh, options in self.pending.values():
            by_mesh.setdefault(mesh, []).append(options)
        env = dict(os.environ, PYTHONPATH=self.python_dir, SHELLCONTRACT_CLI=self.tool)
        os.makedirs(self.sweep_dir, exist_ok=True)
        for k, (mesh, runs) in enumerate(sorted(by_mesh.items())):
            path = os.path.join(self.work, f"sweep_{len(os.listdir(self.work))}_{k}.json")
            with open(path, "w") as f:
                json.dump({"meshes": [mesh], "runs": runs}, f, indent=1)
            cmd = [sys.executable, "-m", "shellcontract.sweep", path, "-o", self.sweep_dir]
            if self.workers:
                cmd += ["--workers", str(self.workers)]
            start = time.time()
            proc = subprocess.run(cmd, env=env, capture_output=True, text=True)
            self.sweep_seconds += time.time() - start
            self.sweeps += 1
            print(f"  sweep of {len(runs)} runs on {os.path.basename(mesh)}: "
                  f"{proc.stderr.strip().splitlines()[-1] if proc.stderr.strip() else ''}",
                  flush=True)
            if proc.returncode == 1:  # refused: a bad option or mesh; nothing ran
                raise RuntimeError(f"{' '.join(cmd)}: exit 1\n{proc.stderr}")

    def _job_id(self, mesh, options):
        data = {"meshes": [mesh], "options": {}, "grid": {}, "runs": [options]}
        jobs = self._sweep_file.expand(os.path.join(self.work, "figures.json"), data,
                                       self.version, check_mesh=lambda m: None)
        return jobs[0].id

    def _record(self, job_id):
        try:
            with open(os.path.join(self.sweep_dir, "jobs", job_id, "job.json")) as f:
                record = json.load(f)
        except (OSError, ValueError):
            return None
        # A crash, a kill or a timeout is run again by the next sweep (as the sweep does).
        return record if record.get("status") not in ("crashed", "killed", "timeout") else None
