"""What a sweep writes or removes in its folder DIR, checked before anything runs by the rule every
command's outputs follow (docs/design/output-safety.md, "One decision for every output"; the
sweep's side of it: docs/design/sweeps.md, "Results"): by file identity, never an input, never
a folder, device, FIFO or socket replaced, never a write-protected file. The library's own check
(check_output_files) is not reachable from Python, and the sweep writes by its own renames, so
the same decisions are taken here, for the sweep's own paths; each job's run checks its own
outputs as every `shellcontract run` does.

What the sweep writes or removes: DIR/results.csv and DIR/results.json (replaced by a rename at
every rewrite), DIR/jobs/<id>/ (a job's folder, replaced when its earlier outcome was not
final), DIR/.work/ (attempts' folders, removed; the jobs' checkpoints, the files beside them and
the jobs' locks in DIR/.work/checkpoints/, written by the runs and removed when a job is done).
"""

import json
import os
import stat

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
    for name in TABLES:
        _replaced_file(os.path.join(out_dir, name), name, ids)
    job_ids = set(job_ids)
    checkpoints = os.path.join(out_dir, ".work", "checkpoints")
    folder = _lstat(checkpoints)
    if folder is not None and not stat.S_ISDIR(folder.st_mode):
        raise OutputError("{}: expected the sweep's folder of the jobs' checkpoints, found {}"
                          .format(checkpoints, _kind(folder.st_mode)))
    jobs = os.path.join(out_dir, "jobs")
    try:
        with os.scandir(jobs) as entries:
            for e in entries:
                if e.name in job_ids and not e.is_dir(follow_symlinks=False):
                    found = _kind(e.stat(follow_symlinks=False).st_mode)
                    raise OutputError("{}: expected the sweep's folder of job {}, found {}; it "
                                      "is never replaced: move it away".format(e.path, e.name,
                                                                               found))
    except FileNotFoundError:
        pass
    except OSError as e:
        raise OutputError("{}: cannot list it ({})".format(jobs, e.strerror or e))
    # No input in a folder the sweep replaces or removes: DIR/.work, and the folder of a job whose
    # outcome is not final (a crash, a timeout: the job runs again and its folder is replaced).
    work, jobs_st = _lstat(os.path.join(out_dir, ".work")), _lstat(jobs)
    work = None if work is None else (work.st_dev, work.st_ino)
    jobs_st = None if jobs_st is None else (jobs_st.st_dev, jobs_st.st_ino)
    for what, path in inputs:
        below = None  # the folder one level below the one reached, going up
        for dev, ino, d in _ancestors(path):
            hit = None
            if (dev, ino) == work:
                hit = d
            elif ((dev, ino) == jobs_st and below is not None
                  and os.path.basename(below) in job_ids and not _final(below)):
                hit = below
            if hit is not None:
                raise OutputError("{} {} is in {}, which the sweep replaces or removes; it is "
                                  "never an input: move it out of the results folder".format(
                                      what, path, hit))
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
