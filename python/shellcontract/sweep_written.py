"""What a sweep writes or removes in its folder DIR, checked before anything runs by the rule every
command's outputs follow (docs/design/output-safety.md, "One decision for every output"; the
sweep's side of it: docs/design/sweeps.md, "Results"): by file identity, never an input, never
a folder, device, FIFO or socket replaced, never a write-protected file. The library's own check
(check_output_files) is not reachable from Python, and the sweep writes by its own renames, so
the same decisions are taken here, for the sweep's own paths; each job's run checks its own
outputs as every `shellcontract run` does. Among them, as the library's: a file of another user
in a sticky folder (the kernel would refuse the rename only when the table is written, after the
jobs), and a file that a mesh needs (an OBJ's .mtl, a texture, a glTF buffer: sweep_needs.py),
never written over nor created.

What the sweep writes or removes: DIR/results.csv and DIR/results.json (replaced by a rename at
every rewrite), DIR/jobs/<id>/ (a job's folder, replaced when its earlier outcome was not
final), DIR/.work/ (attempts' folders, removed; the jobs' checkpoints, the files beside them and
the jobs' locks in DIR/.work/checkpoints/, written by the runs and removed when a job is done).
"""

import json
import os
import stat

from . import sweep_needs

# The tables the sweep rewrites in DIR.
TABLES = ("results.csv", "results.json")
# The files a job keeps in DIR/.work/checkpoints/ (besides its runs' temporaries, which the tool
# creates exclusively): the checkpoint and the two files beside it, which the job's run writes,
# and the sweep's lock of the job.
JOB_FILES = (".ckpt", ".ckpt.log", ".ckpt.history", ".lock")


class OutputError(Exception):
    """DIR cannot be the sweep's (the message names the path and why)."""


def _kind(mode):
    if stat.S_ISLNK(mode):
        return "a link"
    if stat.S_ISDIR(mode):
        return "a folder"
    if stat.S_ISREG(mode):
        return "a file"
    return "a device, FIFO or socket"


def _lstat(path):
    try:
        return os.lstat(path)
    except FileNotFoundError:
        return None
    except OSError as e:
        raise OutputError("{}: cannot examine it ({})".format(path, e.strerror or e))


def _has_cap_fowner():
    """Whether this process may replace any file in a sticky folder (root's CAP_FOWNER, as the
    library's has_cap_fowner asks the kernel)."""
    try:
        with open("/proc/self/status") as f:
            for line in f:
                if line.startswith("CapEff:"):
                    return bool(int(line.split()[1], 16) >> 3 & 1)  # CAP_FOWNER is 3
    except (OSError, ValueError, IndexError):
        pass
    return os.geteuid() == 0


def sticky_problem(st, folder):
    """Why the entry `st` in the folder `folder` (both os.stat results) cannot be replaced or
    removed by this process, or None: the library's sticky_problem (src/mesh/output_target.cpp),
    with its words. In a sticky folder (mode +t, like /tmp) only the file's owner, the folder's
    owner or a process with CAP_FOWNER may rename over or remove an entry; the kernel says so
    only at the rename, after the jobs ran."""
    if not folder.st_mode & stat.S_ISVTX:
        return None
    me = os.geteuid()
    if st.st_uid == me or folder.st_uid == me or _has_cap_fowner():
        return None
    return ("exists and cannot be replaced: it belongs to another user (uid {}) and its folder "
            "is sticky (like /tmp: only the file's owner, the folder's owner or root may replace "
            "or remove a file there); remove it as its owner, or choose another -o folder".format(
                st.st_uid))


def _folder_stat(path):
    try:
        return os.stat(os.path.dirname(os.path.abspath(path)))
    except OSError:
        return None


def _identities(inputs):
    """(device, inode) -> (what, path) of each input (links followed, as the input is read)."""
    out = {}
    for what, path in inputs:
        try:
            st = os.stat(path)
        except OSError:
            continue  # a file the sweep could not read was refused before
        out.setdefault((st.st_dev, st.st_ino), (what, path))
    return out


def _replaced_file(path, name, inputs):
    """One of the tables: absent, or a writable regular file that is no input. A link is refused
    rather than followed: the table is replaced by a rename, which would replace the link."""
    st = _lstat(path)
    if st is None:
        return
    if not stat.S_ISREG(st.st_mode):
        raise OutputError("{}: expected the sweep's {} (a file it replaces at every rewrite), "
                          "found {}; it is never replaced: move it away".format(
                              path, name, _kind(st.st_mode)))
    same = inputs.get((st.st_dev, st.st_ino))
    if same is not None:
        if os.path.realpath(path) != os.path.realpath(same[1]):
            # Another name of the input's file (a hard link): that name is what is in the way.
            raise OutputError("{}: is another name (a hard link) of the sweep's input {} {}; the "
                              "sweep rewrites its {} there, so it is never written: remove or "
                              "rename {} (the input keeps its own name), or choose another -o "
                              "folder".format(path, same[0], same[1], name, path))
        raise OutputError("{}: is the sweep's input {} {} (the same file); the sweep rewrites its "
                          "{} there, so it is never written: move that input out of the results "
                          "folder, or choose another -o folder".format(path, same[0], same[1],
                                                                      name))
    if not st.st_mode & 0o222 or not os.access(path, os.W_OK):
        raise OutputError("{}: it is write-protected (as a user keeps a result); the sweep "
                          "rewrites it: make it writable, or choose another -o folder".format(path))
    folder = _folder_stat(path)
    why = folder and sticky_problem(st, folder)
    if why:
        raise OutputError("{}: {}".format(path, why))


def _same_place(a, b):
    """Whether the paths a and b are one file: the same inode when both exist (a hard link, a
    link), else the same path once links are resolved (a file one of them would create)."""
    try:
        sa, sb = os.stat(a), os.stat(b)
        if (sa.st_dev, sa.st_ino) == (sb.st_dev, sb.st_ino):
            return True
    except OSError:
        pass
    return os.path.realpath(a) == os.path.realpath(b)


def needed_files(inputs):
    """(path, what it is, the mesh) of each file that a mesh of `inputs` needs (sweep_needs)."""
    out, seen = [], set()
    for what, path in inputs:
        if what != "mesh" or path in seen:
            continue
        seen.add(path)
        out.extend((p, role, path) for p, role in sweep_needs.needed_files(path))
    return out


def check_needed(out_dir, needed):
    """No file the sweep writes or creates in DIR (its tables, its marker, jobs/ and .work/) is a
    file that a mesh needs (`needed`: needed_files()), whether or not that file exists: the
    library's rule for every output (output_check.cpp, "the input needs this file"). DIR need
    not exist."""
    from .sweep_output import MARKER, OWNED  # sweep_output imports this module
    for name in OWNED + (MARKER,):
        p = os.path.join(out_dir, name)
        for path, role, mesh in needed:
            if _same_place(p, path):
                raise OutputError(
                    "{}: is {}{}; the mesh needs this file, so the sweep never writes its {} "
                    "there: choose another -o folder".format(
                        p, role, "" if path == p else " ({})".format(path), name))


def _ancestors(path):
    """(device, inode, path) of each folder that holds `path` (links followed), nearest first."""
    out = []
    d = os.path.dirname(os.path.realpath(path))
    while True:
        try:
            st = os.stat(d)
        except OSError:
            return out
        out.append((st.st_dev, st.st_ino, d))
        parent = os.path.dirname(d)
        if parent == d:
            return out
        d = parent


def _final(job_folder):
    from .sweep_job import FINAL_STATUSES  # sweep_job imports this module
    try:
        with open(os.path.join(job_folder, "job.json")) as f:
            return json.load(f).get("status") in FINAL_STATUSES
    except (OSError, ValueError, AttributeError):
        return False


def check_written(out_dir, inputs=(), job_ids=()):
    """Everything the sweep of these inputs and jobs writes or removes in the existing DIR, by
    the output rule; raises OutputError naming the path and why. `inputs`: (what, path) of every
    file the sweep reads (the sweep file, the meshes, the regions and weights files); `job_ids`:
    its jobs' ids. Writes nothing."""
    inputs = list(inputs)
    ids = _identities(inputs)
    needed = needed_files(inputs)
    check_needed(out_dir, needed)
    for name in TABLES:
        _replaced_file(os.path.join(out_dir, name), name, ids)
    job_ids = set(job_ids)
    checkpoints = os.path.join(out_dir, ".work", "checkpoints")
    folder = _lstat(checkpoints)
    if folder is not None and not stat.S_ISDIR(folder.st_mode):
        raise OutputError("{}: expected the sweep's folder of the jobs' checkpoints, found {}"
                          .format(checkpoints, _kind(folder.st_mode)))
    jobs = os.path.join(out_dir, "jobs")
    jobs_folder = _lstat(jobs)
    try:
        with os.scandir(jobs) as entries:
            for e in entries:
                if e.name in job_ids and not e.is_dir(follow_symlinks=False):
                    found = _kind(e.stat(follow_symlinks=False).st_mode)
                    raise OutputError("{}: expected the sweep's folder of job {}, found {}; it "
                                      "is never replaced: move it away".format(e.path, e.name,
                                                                               found))
                # A job whose outcome is not final runs again, and its folder is renamed away.
                if e.name in job_ids and jobs_folder is not None and not _final(e.path):
                    why = sticky_problem(e.stat(follow_symlinks=False), jobs_folder)
                    if why:
                        raise OutputError("{}: {}".format(e.path, why))
    except FileNotFoundError:
        pass
    except OSError as e:
        raise OutputError("{}: cannot list it ({})".format(jobs, e.strerror or e))
    # No input in a folder the sweep replaces or removes: DIR/.work, and the folder of a job whose
    # outcome is not final (a crash, a timeout: the job runs again and its folder is replaced).
    work, jobs_st = _lstat(os.path.join(out_dir, ".work")), _lstat(jobs)
    work = None if work is None else (work.st_dev, work.st_ino)
    jobs_st = None if jobs_st is None else (jobs_st.st_dev, jobs_st.st_ino)
    # A file a mesh needs counts as an input here: the sweep would remove it with its folder.
    named = [("{} {}".format(what, path), path) for what, path in inputs]
    named += [("{} ({}),".format(path, role), path) for path, role, _ in needed]
    for label, path in named:
        below = None  # the folder one level below the one reached, going up
        for dev, ino, d in _ancestors(path):
            hit = None
            if (dev, ino) == work:
                hit = d
            elif ((dev, ino) == jobs_st and below is not None
                  and os.path.basename(below) in job_ids and not _final(below)):
                hit = below
            if hit is not None:
                raise OutputError("{} is in {}, which the sweep replaces or removes; it is "
                                  "never an input: move it out of the results folder".format(
                                      label, hit))
            below = d
    # The jobs' files in DIR/.work/checkpoints: each run writes its checkpoint through a link
    # there, and the sweep removes them: only regular files.
    try:
        entries = os.listdir(checkpoints) if folder is not None else []
    except OSError as e:
        raise OutputError("{}: cannot list it ({})".format(checkpoints, e.strerror or e))
    for name in entries:
        if name[:16] not in job_ids or name[16:] not in JOB_FILES:
            continue
        p = os.path.join(checkpoints, name)
        st = _lstat(p)
        if st is not None and not stat.S_ISREG(st.st_mode):
            raise OutputError("{}: expected the sweep's file of job {}, found {}; it is never "
                              "replaced: move it away".format(p, name[:16], _kind(st.st_mode)))
