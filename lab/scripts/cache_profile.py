#!/usr/bin/env python3
"""Instructions, simulated cache misses and mispredicted branches per face and step, bear against
bear subdivided (issue "Large meshes and many cores", its linear-cost point: where does the step's
cost per face grow?).

Timings on a shared VM vary by up to 40 % between runs; valgrind's cachegrind counts the
instructions each function executes and simulates a two-level data cache and a branch predictor.
From one run of the same binary to the next the instruction counts repeat to within a few hundredths
of a percent, the misses to within a percent or two (the memory layout changes). Each mesh
(scale_benchmark.py's, made deterministically from data/meshes/bear.off) runs `shellcontract run
MESH --frames N --threads 1 --order coloured` and again with --frames 0; the difference, divided by
the faces and the N steps, is what one step costs per face. Writes a markdown page
(lab/pages/cache-profile.md unless --out) with the totals, the solve's and the collision
step's functions grouped by name, and the largest functions.

What cachegrind does not see: valgrind hides AVX-512 from the program, so the broad phase's cell
loop runs its portable version here (the tool takes the AVX-512 one where the CPU has it); the
simulated cache has two levels (--l1, --ll: by default 32 KB and 1 MB; 1 MB is the L2 of a Zen 4
or Zen 5 core), with no prefetcher; and the counts are instructions and misses, not time.

Usage: lab/scripts/cache_profile.py [--build build | --tool PATH] [--frames 3] [--levels 0,2]
                                [--extra "--delta auto"] [--ll 1048576] [--out FILE]
Needs: valgrind, the built tool, data/meshes/bear.off. Bear x16 takes about 12 minutes (two runs
of 10 and 4 minutes, side by side on two cores)."""
import argparse
import collections
import os
import re
import shlex
import shutil
import subprocess
import sys
import tempfile
from concurrent.futures import ThreadPoolExecutor

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "lab", "scripts"))
from scale_benchmark import write_levels  # noqa: E402

# The events the page uses; an event missing from a file (a run without the branch simulation)
# counts 0.
EVENTS = ["Ir", "D1mr", "DLmr", "D1mw", "DLmw", "Bcm", "Bim"]

# Functions grouped by a pattern of their demangled name (first match wins); what matches none is
# "other". The largest functions are listed by name as well, so a group never hides one.
GROUPS = [
    ("solve: dihedral hinges", r"dihedral|atan2|wrapped_angle_difference"),
    ("solve: membrane", r"membrane_batches|GaussSeidelSolver|pack_padded|unpack_padded"),
    ("broad phase: grid build or patch",
     r"grid_sort_count|grid_sort_fill|patch_grid|emit_cells_in_rows|build_grid_vertex_boxes"),
    ("broad phase: cell loop and pair output", r"cell_masks|grid_pairs"),
    ("broad phase: pair records", r"fill_records|Impl::broad_phase|set_regions"),
    ("filter", r"cull_avx2|cull_batch|separating_axis_culls"),
    ("narrow phase", r"Impl::detect|segment_segment_closest|point_triangle_closest|run_ccd|"
                     r"make_closest"),
    ("response rounds", r"mark_moved_and_collect|resolve_impl|warm_start|update_contact_cache|"
                        r"Impl::compact|collect_live|project_contact"),
    ("pressure and volume", r"pressure_forces|signed_volume|GetGeomTraits"),
]


def load(path):
    """Per-function event counts of a cachegrind output file."""
    events, fn = None, None
    counts = collections.defaultdict(lambda: [0] * len(EVENTS))
    with open(path) as f:
        for line in f:
            if line.startswith("events:"):
                events = line.split()[1:]
            elif line.startswith("fn="):
                fn = line[3:].strip()
            elif fn and line[:1].isdigit():
                if events is None:
                    sys.exit(f"cache_profile: {path} has counts before its events line")
                values = line.split()[1:]
                row = counts[fn]
                for i, name in enumerate(EVENTS):
                    at = events.index(name) if name in events else len(values)
                    if at < len(values):
                        row[i] += int(values[at])
    return counts


def cachegrind(tool, mesh, frames, extra, l1, ll, out):
    cmd = ["valgrind", "--tool=cachegrind", "--cache-sim=yes", "--branch-sim=yes",
           f"--I1={l1},8,64", f"--D1={l1},8,64", f"--LL={ll},16,64",
           f"--cachegrind-out-file={out}", tool, "run", mesh, "-o", out + ".off", "--frames",
           str(frames), "--threads", "1", "--order", "coloured", "-q"] + extra
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode != 0:
        sys.exit(f"{' '.join(cmd)} failed:\n{p.stdout}{p.stderr}")
    return load(out)


def per_face_step(run, setup, faces, steps):
    """Each function's counts of the run less the set-up run's, per face and step."""
    out = {}
    for fn in set(run) | set(setup):
        a, b = run.get(fn, [0] * len(EVENTS)), setup.get(fn, [0] * len(EVENTS))
        out[fn] = [(x - y) / faces / steps for x, y in zip(a, b)]
    return out


def group_of(fn):
    """The part of the step a function belongs to (GROUPS, first match), or "other"."""
    for name, pattern in GROUPS:
        if re.search(pattern, fn):
            return name
    return "other"


def short(fn):
    """The function's name without its arguments and template arguments; a TBB task by the first
    of our functions in its template arguments (the loop body it runs)."""
    if fn.startswith(("tbb::", "void tbb::")):
        inner = re.search(r"shellcontract::[A-Za-z_:]*[A-Za-z_]", fn)
        if inner:
            return "TBB task of " + short(inner.group(0))
    s = fn
    while True:
        t = re.sub(r"<[^<>]*>", "", s)
        if t == s:
            break
        s = t
    s = re.sub(r"\(anonymous namespace\)::", "", s)
    s = re.sub(r"\([^()]*\)", "", s)
    s = re.sub(r"\([^()]*\)", "", s)
    return s.replace("|", "/")[:90]


def ratio(a, b):
    """a / b, or "-" where b is too small a count for a ratio to mean anything."""
    return f"{a / b:.2f}x" if b >= 0.05 else "-"


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--tool", help="the tool to profile (default: BUILD/shellcontract)")
    ap.add_argument("--frames", type=int, default=3)
    ap.add_argument("--levels", default="0,2", help="subdivision levels; the first is the base")
    ap.add_argument("--extra", default="", help="more options for every run")
    ap.add_argument("--l1", type=int, default=32768, help="simulated L1 size (bytes)")
    ap.add_argument("--ll", type=int, default=1048576, help="simulated last level (bytes)")
    ap.add_argument("--top", type=int, default=25)
    ap.add_argument("--out", default=os.path.join(ROOT, "lab", "pages", "cache-profile.md"))
    a = ap.parse_args()
    tool = a.tool or os.path.join(a.build, "shellcontract")
    try:
        levels = [int(x) for x in a.levels.split(",")]
    except ValueError:
        sys.exit(f"cache_profile: --levels {a.levels!r} is not a list of integers like 0,2")
    if a.frames < 1 or len(levels) < 2 or min(levels) < 0:
        sys.exit("cache_profile: need --frames >= 1 and at least two levels >= 0")
    bear = os.path.join(ROOT, "data", "meshes", "bear.off")
    if not os.path.exists(bear):
        sys.exit(f"cache_profile: {bear} is missing (scripts/fetch_paper_meshes.sh)")
    extra = shlex.split(a.extra)
    if shutil.which("valgrind") is None:
        sys.exit("cache_profile: valgrind not found (Debian: apt-get install valgrind)")
    if not os.access(tool, os.X_OK):
        sys.exit(f"cache_profile: no tool at {tool} (build it first, or give --tool)")
    with tempfile.TemporaryDirectory() as tmp:
        meshes = write_levels(tmp, levels)
        jobs = [(lv, n) for lv in levels for n in (a.frames, 0)]
        with ThreadPoolExecutor(max_workers=2) as pool:
            futures = {job: pool.submit(cachegrind, tool, meshes[job[0]][0], job[1], extra, a.l1,
                                        a.ll, os.path.join(tmp, f"cg_{job[0]}_{job[1]}.out"))
                       for job in jobs}
            counts = {job: f.result() for job, f in futures.items()}
    rows = {lv: per_face_step(counts[(lv, a.frames)], counts[(lv, 0)], meshes[lv][1], a.frames)
            for lv in levels}
    write_page(a, levels, meshes, rows)


def write_page(a, levels, meshes, rows):
    base, names = levels[0], {lv: f"bear x{4 ** lv}" if lv else "bear" for lv in levels}
    ir, d1, ll = EVENTS.index("Ir"), EVENTS.index("D1mr"), EVENTS.index("DLmr")
    d1w, llw = EVENTS.index("D1mw"), EVENTS.index("DLmw")

    def mispredicts(v):
        return v[EVENTS.index("Bcm")] + v[EVENTS.index("Bim")]
    lines = [f"# Instructions, cache misses and mispredicted branches per face and step: "
             f"{', '.join(names.values())}", "",
             f"`/usr/bin/python3 lab/scripts/cache_profile.py --frames {a.frames} --levels {a.levels}"
             + (f' --extra "{a.extra}"' if a.extra else "")
             + (f" --tool {a.tool}" if a.tool else "")
             + (f" --l1 {a.l1}" if a.l1 != 32768 else "") + f" --ll {a.ll}` (writes this page; "
             f"valgrind's cachegrind, one thread, coloured order; the run of `--frames "
             f"{a.frames}` less the run of `--frames 0`, per face and step). Simulated caches: "
             f"L1 {a.l1 // 1024} KB 8-way, last level {a.ll // 1024} KB 16-way, 64-byte lines, "
             "no prefetcher; branches through cachegrind's simulated predictor (conditional "
             "and indirect, mispredictions counted). From one run of the same build to the next "
             "the instruction counts repeat to within a few hundredths of a percent, the misses "
             "to within a percent or two; they are counts, not time. Under valgrind the cell loop "
             "runs its portable version, not the AVX-512 one.", ""]
    lines += ["## The whole step", "",
              "| mesh | faces | instructions | L1 read misses | last-level read misses | "
              "L1 write misses | last-level write misses | mispredicted branches |",
              "|---|---:|---:|---:|---:|---:|---:|---:|"]
    tot = {lv: [sum(v[i] for v in rows[lv].values()) for i in range(len(EVENTS))]
           for lv in levels}
    for lv in levels:
        t = tot[lv]
        lines.append(f"| {names[lv]} | {meshes[lv][1]} | {t[ir]:.0f} | {t[d1]:.1f} | {t[ll]:.1f} "
                     f"| {t[d1w]:.1f} | {t[llw]:.1f} | {mispredicts(t):.2f} |")
    for lv in levels[1:]:
        t, b = tot[lv], tot[base]
        lines.append(f"| {names[lv]} / {names[base]} | | {ratio(t[ir], b[ir])} | "
                     f"{ratio(t[d1], b[d1])} | {ratio(t[ll], b[ll])} | {ratio(t[d1w], b[d1w])} | "
                     f"{ratio(t[llw], b[llw])} | {ratio(mispredicts(t), mispredicts(b))} |")
    lines += ["", "## By part of the step (functions grouped by name)", "",
              "Per face and step: instructions, last-level read misses and mispredicted branches; "
              f"each with the ratio to {names[base]}'s. Each count is the difference of two runs, "
              "so a part whose work the run of 0 frames also does (reading, preparing) can come "
              "out a little below zero.", ""]
    measures = [("instr.", lambda v: v[ir], "{:.0f}"),
                ("LL read misses", lambda v: v[ll], "{:.2f}"),
                ("mispredicts", mispredicts, "{:.2f}")]
    head = "| part | " + " | ".join(f"{label}, {names[lv]}" for label, _, _ in measures
                                    for lv in levels) + " |"
    lines += [head, "|---|" + "---:|" * (len(measures) * len(levels))]
    groups = {lv: collections.defaultdict(lambda: [0.0] * len(EVENTS)) for lv in levels}
    for lv in levels:
        for fn, v in rows[lv].items():
            g = groups[lv][group_of(fn)]
            for i in range(len(EVENTS)):
                g[i] += v[i]
    for name in [g for g, _ in GROUPS] + ["other"]:
        cells = []
        for _, value, fmt in measures:
            for lv in levels:
                x, b = value(groups[lv][name]), value(groups[base][name])
                cells.append(fmt.format(x) if lv == base else f"{fmt.format(x)} ({ratio(x, b)})")
        lines.append(f"| {name} | " + " | ".join(cells) + " |")
    last = levels[-1]
    lines += ["", f"## The largest functions of {names[last]}", "",
              f"By instructions per face and step on {names[last]}.", "",
              "| function | part | " + " | ".join(f"instr., {names[lv]}" for lv in levels)
              + " | " + " | ".join(f"L1 read misses, {names[lv]}" for lv in levels) + " | "
              + " | ".join(f"LL read misses, {names[lv]}" for lv in levels) + " |",
              "|---|---|" + "---:|" * (3 * len(levels))]
    top = sorted(rows[last], key=lambda fn: -rows[last][fn][ir])[:a.top]
    for fn in top:
        cells = []
        for i, fmt in ((ir, "{:.0f}"), (d1, "{:.2f}"), (ll, "{:.2f}")):
            cells += [fmt.format(rows[lv].get(fn, [0.0] * len(EVENTS))[i]) for lv in levels]
        lines.append(f"| `{short(fn)}` | {group_of(fn)} | " + " | ".join(cells) + " |")
    os.makedirs(os.path.dirname(os.path.abspath(a.out)), exist_ok=True)
    with open(a.out, "w") as f:
        f.write("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
