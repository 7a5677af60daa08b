#!/usr/bin/python3
"""Runs shellcontract over every mesh of CGAL's demo data (Debian's libcgal-demo, the package the
paper's meshes come from) and writes a markdown table (lab/pages/corpus.md by default).

Per mesh: `check --json` on the file; `repair --json` on the file when check refuses it; and a
default run (200 frames unless --frames, `--validate end`) on every mesh check accepts and on every
repaired one, each with a timeout; then `check --json` on the run's output, to count the
self-intersecting face pairs after the run.

Usage: /usr/bin/python3 lab/scripts/corpus_run.py [--cli build/shellcontract] [--out lab/pages/corpus.md]
           [--timeout 120] [--run-timeout 300] [--frames 200] [--jobs 1] [--only camel.off,bear.off]
           [--no-run] [--work DIR [--reuse]]
The corpus is extracted to a temporary folder (or --work DIR, kept) and never into the repository.
"""
import argparse
import concurrent.futures
import json
import os
import subprocess
import sys
import tarfile
import tempfile
import time

MESH_EXT = (".off", ".obj", ".ply", ".stl")


def corpus_tarball():
    out = subprocess.run(["dpkg", "-L", "libcgal-demo"], capture_output=True, text=True)
    for line in out.stdout.splitlines():
        if line.endswith("/data.tar.gz") and os.path.isfile(line):
            return line
    sys.exit("error: libcgal-demo's data.tar.gz not found (apt-get install libcgal-demo)")


def extract(tarball, dest):
    with tarfile.open(tarball) as t:
        members = [m for m in t.getmembers()
                   if m.isfile() and m.name.startswith("data/meshes/") and m.name.lower().endswith(MESH_EXT)]
        t.extractall(dest, members=members)
    return sorted(os.path.join(dest, m.name) for m in members)


def call(cmd, timeout):
    """(exit code or 'timeout', stdout, stderr, seconds)."""
    start = time.monotonic()
    try:
        p = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
        return p.returncode, p.stdout, p.stderr, time.monotonic() - start
    except subprocess.TimeoutExpired:
        return "timeout", "", "", time.monotonic() - start


def last_json(text):
    """The JSON object that a --json command prints on stdout ({} if none)."""
    start = text.find("{")
    try:
        return json.loads(text[start:]) if start >= 0 else {}
    except ValueError:
        return {}


def problem(stderr):
    """The problem name of an InputError message, "<file>: <problem>: <details>"."""
    line = stderr.strip().splitlines()[-1] if stderr.strip() else ""
    parts = line.split(": ")
    return parts[2] if len(parts) > 2 else line


def one_mesh(path, args, work):
    name = os.path.basename(path)
    stem = os.path.join(work, "out", name.replace("^", "_"))
    row = {"mesh": name, "faces": "", "check": "", "repair": "", "run": "", "ratio": "", "seconds": "",
           "si_before": "", "si_after": "", "usable": False, "repaired": False}
    rc, out, err, _ = call([args.cli, "check", path, "--json"], args.timeout)
    rep = last_json(out)
    run_input = None
    if rc == 0:
        row["check"] = "usable"
        row["faces"] = rep.get("faces", "")
        row["si_before"] = rep.get("self_intersecting_pairs", "")
        row["usable"] = True
        run_input = path
    else:
        row["check"] = "timeout" if rc == "timeout" else "refused: " + problem(err)
        repaired = stem + ".repaired.off"
        rc, out, err, _ = call([args.cli, "repair", path, "-o", repaired, "--json"], args.timeout)
        rep = last_json(out)
        if rc == 0:
            holes = rep.get("holes_filled", 0)
            dropped = rep.get("components_dropped", 0)
            row["repair"] = f"usable ({holes} holes filled, {rep.get('hole_faces_added', 0)} faces added, " + \
                f"largest hole {rep.get('largest_hole_edges', 0)} edges" + \
                (f", {dropped} components dropped" if dropped else "") + ")"
            row["repaired"] = True
            rc2, out2, _, _ = call([args.cli, "check", repaired, "--json"], args.timeout)
            rep2 = last_json(out2)
            row["faces"] = rep2.get("faces", "")
            row["si_before"] = rep2.get("self_intersecting_pairs", "")
            run_input = repaired
        else:
            row["repair"] = "timeout" if rc == "timeout" else "refused: " + (rep.get("failure") or problem(err))
    result = stem + ".run.off"
    summary = stem + ".summary.json"
    if run_input is None:
        return row
    if args.reuse and os.path.exists(summary) and os.path.exists(result):
        # A previous run of this script with the same --work: its summary stands for the run.
        with open(summary) as f:
            s = json.load(f)
        rc, secs = s.get("exit_code", ""), s.get("wall_seconds", float("nan"))
    elif args.no_run:
        return row
    else:
        rc, _, err, secs = call([args.cli, "run", run_input, "-o", result, "--validate", "end", "-q",
                                 "--frames", str(args.frames), "--summary", summary, "--threads", "1"],
                                args.run_timeout)
    row["run"] = rc
    row["seconds"] = f"{secs:.1f}"
    if rc != "timeout" and os.path.exists(summary):
        with open(summary) as f:
            s = json.load(f)
        row["ratio"] = f"{s.get('final_volume_ratio', float('nan')):.3f}"
        row["seconds"] = f"{s.get('wall_seconds', secs):.1f}"  # the simulation's, not the process's
        if rc == 3:
            row["run"] = f"3 ({s.get('failure', '').split(':')[0]})"
    if rc != "timeout" and os.path.exists(result):
        _, out, _, _ = call([args.cli, "check", result, "--json"], args.timeout)
        row["si_after"] = last_json(out).get("self_intersecting_pairs", "")
    return row


def main():
    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--cli", default=os.path.join(root, "build", "shellcontract"))
    ap.add_argument("--out", default=os.path.join(root, "lab", "pages", "corpus.md"))
    ap.add_argument("--timeout", type=float, default=120, help="seconds for check and repair")
    ap.add_argument("--run-timeout", type=float, default=300, help="seconds for one run")
    ap.add_argument("--frames", type=int, default=200)
    ap.add_argument("--jobs", type=int, default=1)
    ap.add_argument("--only", default="", help="comma-separated mesh file names")
    ap.add_argument("--no-run", action="store_true", help="check and repair only")
    ap.add_argument("--reuse", action="store_true",
                    help="with --work: take the runs whose summary a previous call left there")
    ap.add_argument("--work", default="", help="extract and write here (kept) instead of a temporary folder")
    args = ap.parse_args()

    with tempfile.TemporaryDirectory() as tmp:
        work = args.work or tmp
        os.makedirs(os.path.join(work, "out"), exist_ok=True)
        meshes = extract(corpus_tarball(), work)
        if args.only:
            wanted = set(args.only.split(","))
            meshes = [m for m in meshes if os.path.basename(m) in wanted]
        start = time.monotonic()
        with concurrent.futures.ThreadPoolExecutor(max_workers=args.jobs) as pool:
            rows = list(pool.map(lambda m: one_mesh(m, args, work), meshes))
        elapsed = time.monotonic() - start

    n = len(rows)
    usable = sum(r["usable"] for r in rows)
    repaired = sum(r["repaired"] for r in rows)
    ran = [r for r in rows if r["run"] != ""]
    ok = sum(1 for r in ran if r["run"] == 0)

    def number(v):
        try:
            return float(v)
        except (TypeError, ValueError):
            return None

    # Issue 30 item 6's property: the run ends (exit 0), right side out (V/V0 > 0), and no more
    # self-intersecting pairs after it than before.
    blowups = [r["mesh"] for r in ran if str(r["run"]).startswith("3")]
    timeouts = [r["mesh"] for r in ran if r["run"] == "timeout"]
    inside_out = [r["mesh"] for r in ran if (number(r["ratio"]) or 0.0) < 0.0]
    si_growth = [r["mesh"] for r in ran if number(r["si_after"]) is not None and number(r["si_before"]) is not None
                 and number(r["si_after"]) > number(r["si_before"])]
    refused = [r for r in rows if not r["usable"] and not r["repaired"]]
    lines = [
        "# CGAL demo corpus: check, repair and a default run",
        "",
        f"Made by `/usr/bin/python3 lab/scripts/corpus_run.py {' '.join(sys.argv[1:])}` "
        f"({time.strftime('%Y-%m-%d', time.gmtime())}, {elapsed / 60:.0f} min); the meshes are the "
        "`data/meshes` of Debian's libcgal-demo `data.tar.gz`.",
        "",
        f"- {n} meshes; usable as read: {usable} ({100 * usable / max(n, 1):.0f} %); "
        f"usable after `repair`: {usable + repaired} ({100 * (usable + repaired) / max(n, 1):.0f} %).",
        f"- runs (`run --validate end`, {args.frames} frames, timeout {args.run_timeout:.0f} s): "
        f"{len(ran)}, exit 0: {ok}; others: "
        + (", ".join(f"{r['mesh']} {r['run']}" for r in ran if r["run"] != 0) or "none") + ".",
        f"- refused even after `repair`: {len(refused)}; blow-ups (exit 3): {len(blowups)}"
        + (f" ({', '.join(blowups)})" if blowups else "") + f"; cut off by the timeout: {len(timeouts)}"
        + (f" ({', '.join(timeouts)})" if timeouts else "") + f"; inside out at the end (V/V0 < 0): "
        f"{len(inside_out)}" + (f" ({', '.join(inside_out)})" if inside_out else "")
        + f"; more self-intersecting pairs after the run than before: {len(si_growth)}"
        + (f" ({', '.join(si_growth)})" if si_growth else "") + ".",
        "- self-intersections: face pairs of the run's input (`before`) and of its result (`after`), "
        "by `check`; time: the run's `wall_seconds` (summary), one thread.",
        "",
        "| mesh | faces | check | repair | run exit | V/V0 | time (s) | SI before | SI after |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        lines.append("| {mesh} | {faces} | {check} | {repair} | {run} | {ratio} | {seconds} | {si_before} | {si_after} |"
                     .format(**{k: str(v).replace("|", "/") for k, v in r.items()}))
    with open(args.out, "w") as f:
        f.write("\n".join(lines) + "\n")
    print("\n".join(lines[:8]))


if __name__ == "__main__":
    main()
