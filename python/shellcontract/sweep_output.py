"""The sweep's output folder DIR (docs/design/sweeps.md, "Results"): a folder of one sweep file,
marked as such by DIR/.shellcontract-sweep.json, so that the sweep never writes over files it did
not write (a results.csv of the user's, the folder of the sweep file itself) and two sweep files
never share one results table."""

import fcntl
import json
import os
import re
import stat
import time
import uuid

from . import sweep_written
from .sweep_written import TABLES

MARKER = ".shellcontract-sweep.json"
# The entries the sweep writes in DIR (besides the marker and its temporary files).
OWNED = ("results.csv", "results.json", "jobs", ".work")


# The temporaries of write_atomic: "<name>.tmp-" and 32 hexadecimal digits.
_TEMPORARY = re.compile(r"\A(.+)\.tmp-[0-9a-f]{32}\Z")
# How old a temporary must be before a later sweep removes it, besides unlocked: its writer locks
# it right after creating it, and a writer of an earlier version of the sweep did not lock it at
# all but was done with it within moments.
STALE_TEMPORARY_SECONDS = 60.0


def write_atomic(path, text):
    """`text` into `path` through an exclusive temporary beside it, renamed over it: the file is
    whole or as before, and a failed write (a full disk, Ctrl-C, SIGTERM: KeyboardInterrupt)
    leaves no temporary behind. The temporary is locked (flock) until it is renamed or removed,
    so that one left by a sweep killed with SIGKILL is told from one being written by another
    shard (remove_stale_temporaries). A file replaced keeps its permissions, as the CLI's outputs
    do (a results.csv made private, 0600, stays private; before, it became 0666 less the umask);
    a new one gets 0666 less the umask. Best effort: a file system without modes (FAT) refuses
    chmod, and the file is still written."""
    tmp = "{}.tmp-{}".format(path, uuid.uuid4().hex)
    try:
        with open(tmp, "x", newline="") as f:
            try:
                fcntl.flock(f.fileno(), fcntl.LOCK_EX | fcntl.LOCK_NB)
            except OSError:
                pass  # a file system without locks: only its age tells it is stale
            try:
                before = os.stat(path)
            except OSError:
                before = None
            if before is not None and stat.S_ISREG(before.st_mode):
                try:
                    os.fchmod(f.fileno(), stat.S_IMODE(before.st_mode))
                except OSError:
                    pass
            f.write(text)
            f.flush()
            os.replace(tmp, path)  # while it is locked
    except BaseException:
        try:
            os.remove(tmp)
        except OSError:
            pass
        raise


def _remove_unlocked(path, st):
    """Removes the file `path` (`st`: its lstat) when no process holds a lock on it, holding the
    lock while it does so; whether it did. Nothing where the file system has no locks."""
    try:
        fd = os.open(path, os.O_RDWR | os.O_NOFOLLOW | os.O_NONBLOCK)
    except OSError:
        return False
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        now = os.fstat(fd)
        if (now.st_dev, now.st_ino) != (st.st_dev, st.st_ino):
            return False
        os.remove(path)
        return True
    except OSError:  # BlockingIOError: a writer holds it; another error: no locks here
        return False
    finally:
        os.close(fd)


def remove_stale_temporaries(out_dir, names=TABLES):
    """Removes the temporaries of DIR's tables (`names`) that a sweep killed while writing one
    (SIGKILL, a power cut) left; the number removed. Only a file that is provably the sweep's
    own and abandoned: named as write_atomic names them, a regular file of this user's with no
    other name (a hard link of it would be a user's file), unchanged for
    STALE_TEMPORARY_SECONDS and locked by no process (a shard writing its table holds the lock).
    Where the file system has no locks, none is removed."""
    try:
        entries = os.listdir(out_dir)
    except OSError:
        return 0
    removed = 0
    for name in entries:
        m = _TEMPORARY.match(name)
        if not m or m.group(1) not in names:
            continue
        p = os.path.join(out_dir, name)
        try:
            st = os.lstat(p)
        except OSError:
            continue
        if (stat.S_ISREG(st.st_mode) and st.st_uid == os.geteuid() and st.st_nlink == 1
                and time.time() - st.st_mtime >= STALE_TEMPORARY_SECONDS
                and _remove_unlocked(p, st)):
            removed += 1
    return removed


OutputError = sweep_written.OutputError
check_written = sweep_written.check_written


def _read_marker(path):
    """The marker's sweep file; another shard may be writing it right now (it is created empty,
    then written), so an empty or half-written one is read again for a little while."""
    deadline = time.monotonic() + 5.0
    while True:
        try:
            with open(path) as f:
                data = json.load(f)
            if isinstance(data, dict) and isinstance(data.get("sweep_file"), str):
                return data["sweep_file"]
            problem = "it names no sweep file"
        except ValueError as e:
            problem = "not valid JSON ({})".format(e)
        except OSError as e:
            raise OutputError("{}: cannot read it ({})".format(path, e.strerror or e))
        if time.monotonic() > deadline:
            raise OutputError("{}: the sweep's marker is damaged ({}); it says which sweep file "
                              "the folder's results belong to".format(path, problem))
        time.sleep(0.05)


def check(out_dir, sweep_path, inputs=(), job_ids=()):
    """Whether DIR can hold this sweep file's results, without writing anything: it does not
    exist, or it is empty, or its marker names this sweep file and what the sweep would write or
    remove there passes check_written (`inputs`: (what, path) of every file the sweep reads,
    `job_ids`: its jobs'). Raises OutputError otherwise."""
    sweep_file = os.path.realpath(sweep_path)
    inputs = list(inputs)
    if not os.path.exists(out_dir):
        if os.path.islink(out_dir):
            raise OutputError("{}: a link to nothing, not a folder".format(out_dir))
        # It will be made with its parents: the nearest one that exists must be a folder that
        # takes new entries (a file there ended the real run only, --dry-run said yes).
        parent = os.path.dirname(os.path.abspath(out_dir))
        while not os.path.exists(parent) and os.path.dirname(parent) != parent:
            parent = os.path.dirname(parent)
        if not os.path.isdir(parent):
            raise OutputError("{}: {} is a file, not a folder".format(out_dir, parent))
        if not os.access(parent, os.W_OK | os.X_OK):
            raise OutputError("{}: the folder {} cannot take new entries".format(out_dir, parent))
        sweep_written.check_needed(out_dir, sweep_written.needed_files(inputs))
        return
    if not os.path.isdir(out_dir):
        raise OutputError("{}: not a folder (-o names the folder the results go to)".format(
            out_dir))
    try:
        entries = sorted(os.listdir(out_dir))
    except OSError as e:
        raise OutputError("{}: cannot list it ({})".format(out_dir, e.strerror or e))
    if MARKER in entries:
        owner = _read_marker(os.path.join(out_dir, MARKER))
        if owner != sweep_file and not os.path.exists(owner):
            # A study folder moved or renamed with its sweep file: "edit that file" named a file
            # that is not there.
            raise OutputError(
                "{} holds the results of another sweep file, {}, which no longer exists (moved or "
                "renamed?); a folder holds one sweep file's results: to go on with these from {}, "
                "set \"sweep_file\" in {} to it (its finished jobs are kept), or choose another -o "
                "folder".format(out_dir, owner, sweep_file, os.path.join(out_dir, MARKER)))
        if owner != sweep_file:
            raise OutputError(
                "{} holds the results of another sweep file, {}; a folder holds one sweep file's "
                "results (its table lists that file's jobs): choose another -o folder, or edit "
                "that file and run it again (its finished jobs are kept)".format(out_dir, owner))
        for name in OWNED:
            p = os.path.join(out_dir, name)
            want_dir = name in ("jobs", ".work")
            if os.path.lexists(p) and (os.path.isdir(p) != want_dir or os.path.islink(p)):
                raise OutputError("{}: expected the sweep's {}, found {}".format(
                    p, "folder" if want_dir else "file",
                    "a link" if os.path.islink(p) else "a folder" if os.path.isdir(p) else
                    "a file"))
        check_written(out_dir, inputs, job_ids)
        return
    if entries:
        shown = ", ".join(entries[:5]) + (", ..." if len(entries) > 5 else "")
        raise OutputError(
            "{} holds files that no sweep wrote ({}); the sweep writes results.csv, results.json, "
            "jobs/ and .work/ there: choose a new or empty -o folder".format(out_dir, shown))
    sweep_written.check_needed(out_dir, sweep_written.needed_files(inputs))


def claim(out_dir, sweep_path, inputs=(), job_ids=()):
    """check(), then DIR made the sweep file's: created with its marker, jobs/ and .work/.
    Shards of one sweep may claim the same new folder at once."""
    check(out_dir, sweep_path, inputs, job_ids)
    sweep_file = os.path.realpath(sweep_path)
    marker = os.path.join(out_dir, MARKER)
    try:
        os.makedirs(out_dir, exist_ok=True)
        try:
            fd = os.open(marker, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o644)
        except FileExistsError:
            # A shard of the same sweep got here first (or check() saw the marker already).
            owner = _read_marker(marker)
            if owner != sweep_file:
                raise OutputError("{} holds the results of another sweep file, {}".format(
                    out_dir, owner))
        else:
            with os.fdopen(fd, "w") as f:
                json.dump({"sweep_file": sweep_file,
                           "written_by": "shellcontract sweep (docs/design/sweeps.md)"}, f,
                          indent=1)
                f.write("\n")
        for name in ("jobs", ".work"):
            os.makedirs(os.path.join(out_dir, name), exist_ok=True)
    except OSError as e:
        raise OutputError("{}: {}".format(e.filename or out_dir, e.strerror or e))
