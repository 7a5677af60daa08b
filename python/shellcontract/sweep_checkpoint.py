"""A sweep job's checkpoint, DIR/.work/checkpoints/<id>.ckpt, and the files the tool keeps with
it: what the tool's messages say about it, and its removal when the job is done
(docs/design/sweeps.md, "Jobs").

The messages are matched as the tool writes them: paths through its printable() (a non-UTF-8
byte, a tab or a newline written as \\xNN, cut after 200 characters), so the messages file is
read as bytes and the path escaped the same way here.
"""

import fcntl
import os
import re

from . import sweep_lock


def paths(out_dir, job_id):
    return {
        "final": os.path.join(out_dir, "jobs", job_id),
        "work": os.path.join(out_dir, ".work"),
        "checkpoint": os.path.join(out_dir, ".work", "checkpoints", job_id + ".ckpt"),
    }


# ------------------------------------------------------------------ the tool's names and texts

def _utf8_length(s, i):
    """src/mesh/file_safety.cpp's utf8_length: the length of the well-formed UTF-8 sequence at
    s[i] (no overlong forms, no surrogates, at most U+10FFFF, no C1 control), 0 if none."""
    c = s[i]
    n, lo, hi = 0, 0x80, 0xBF
    if 0xC2 <= c <= 0xDF:
        n = 2
    elif c == 0xE0:
        n, lo = 3, 0xA0
    elif c == 0xED:
        n, hi = 3, 0x9F
    elif 0xE1 <= c <= 0xEF:
        n = 3
    elif c == 0xF0:
        n, lo = 4, 0x90
    elif 0xF1 <= c <= 0xF3:
        n = 4
    elif c == 0xF4:
        n, hi = 4, 0x8F
    if n == 0 or i + n > len(s) or not lo <= s[i + 1] <= hi:
        return 0
    if any(not 0x80 <= s[i + k] <= 0xBF for k in range(2, n)):
        return 0
    if c == 0xC2 and s[i + 1] <= 0x9F:
        return 0
    return n


def printable(path, max_chars=200):
    """The tool's printable(path) (src/mesh/file_safety.cpp), as bytes."""
    s = os.fsencode(path)
    out = bytearray()
    i = 0
    while i < len(s):
        if len(out) >= max_chars:
            out += b"..."
            break
        c = s[i]
        n = (0 if c < 0x20 or c == 0x7F else 1) if c < 0x80 else _utf8_length(s, i)
        if n == 0:
            out += b"\\x%02x" % c
            i += 1
        else:
            out += s[i:i + n]
            i += n
    return bytes(out)


def tool_lock_path(checkpoint):
    """The tool's lock for `checkpoint` (checkpoint_lock_path: ".<name>.lock" beside it; a job's
    name is far from the length at which the tool cuts it)."""
    folder, name = os.path.split(checkpoint)
    return os.path.join(folder, "." + name + ".lock")


def _temporary_pattern(checkpoint):
    """The names of the tool's temporaries of `checkpoint` (write_file_atomic's
    create_registered_temporary: "." + the first 40 characters of "<name>.tmp" + "." + 12 of
    [A-Za-z0-9])."""
    hint = (os.path.basename(checkpoint) + ".tmp")[:40]
    return re.compile(r"\A\." + re.escape(hint) + r"\.[A-Za-z0-9]{12}\Z")


def tool_lines(work):
    """The tool's error lines in the attempt's messages.txt, as bytes (not a note that names the
    file)."""
    try:
        with open(os.path.join(work, "messages.txt"), "rb") as f:
            text = f.read()
    except OSError:
        return []
    return [line.strip() for line in text.splitlines() if line.startswith(b"shellcontract run: ")]


# A read of the checkpoint or a file beside that failed for the machine, not for the file's
# contents (EIO, EMFILE, ESTALE, EACCES: file_safety.cpp's "cannot open file" / "cannot read file"
# with any reason but these two, which say what is, or is not, at the path).
_READ_FAILED = re.compile(rb": cannot (?:open|read) file: (?!no such file|it is a folder)")


def checkpoint_error(work, checkpoint):
    """How the tool failed on `checkpoint` when it exited 2: ("refused", line) when it refused
    its contents (damaged, another run's, its files beside missing or not its own), ("not read",
    line) when the file could not be read, else None (the error is another input's)."""
    named = b"checkpoint " + printable(checkpoint)
    for line in tool_lines(work):
        at = line.find(named)
        if at < 0 or line[at + len(named):at + len(named) + 1] not in (b":", b" "):
            continue
        kind = "not read" if _READ_FAILED.search(line, at + len(named)) else "refused"
        return kind, line.decode("utf-8", "replace")
    return None


def held_by_another_run(work, checkpoint):
    """The tool's refusal (exit 1) because another run holds `checkpoint`'s lock (checkpoint_lock
    .cpp: "... another shellcontract run is saving to this checkpoint or resuming from it (it holds
    'LOCK')"), or None."""
    held = b"(it holds '" + printable(tool_lock_path(checkpoint), 1000) + b"')"
    for line in tool_lines(work):
        if b"another shellcontract run is saving to this checkpoint" in line and held in line:
            return line.decode("utf-8", "replace")
    return None


# ------------------------------------------------------------------------------------ removal

def _tool_lock_free(checkpoint):
    """True when no run holds the tool's lock of `checkpoint` (a run of the job that outlived the
    sweep's own lock: a file system that passes one lock and not the other). The lock file is
    the tool's: left as it is (a run ended by SIGKILL leaves it unlocked; the next run takes it)."""
    try:
        fd = os.open(tool_lock_path(checkpoint), os.O_RDONLY | os.O_NOFOLLOW)
    except OSError:
        return True  # none there (or none this process may open): no run holds it
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except BlockingIOError:
        return False
    except OSError:
        pass  # no locks here
    finally:
        os.close(fd)
    return True


def _is_job_file(job_id, name):
    """One of the names remove_files removes for the job."""
    base = job_id + ".ckpt"
    return name in (base, base + ".log", base + ".history") or bool(
        _temporary_pattern(base).match(name))


def remove_files(out_dir, job_id, names=None):
    """Removes the job's checkpoint, the log and volume history the tool keeps beside it
    (`checkpoint_log_path`, `checkpoint_history_path`: FILE.log, FILE.history) and the
    temporaries of its saves that a run ended by SIGKILL left (each as large as the checkpoint);
    only those names. The caller holds the job's lock; while a run holds the tool's lock they are
    kept, and False returned. `names`: the checkpoints folder's listing, if the caller has it."""
    checkpoint = paths(os.path.abspath(out_dir), job_id)["checkpoint"]
    folder = os.path.dirname(checkpoint)
    if not _tool_lock_free(checkpoint):
        return False
    if names is None:
        try:
            names = os.listdir(folder)
        except OSError:
            names = []
    for name in names:
        if _is_job_file(job_id, name):
            try:
                os.remove(os.path.join(folder, name))
            except OSError:
                pass
    return True


def remove_done(out_dir, job_ids):
    """The files of remove_files, for jobs that a sweep finds done: one killed between
    publishing a job and this removal left them. A job whose lock another attempt holds keeps
    them (that attempt finds the job done and removes them)."""
    out_dir = os.path.abspath(out_dir)
    folder = os.path.join(out_dir, ".work", "checkpoints")
    try:
        names = os.listdir(folder)
    except OSError:
        return
    by_job = {}  # the folder is listed once, not once per job: "<id>.ckpt...", ".<id>.ckpt..."
    for name in names:
        by_job.setdefault(name.lstrip(".")[:16], []).append(name)
    for job_id in job_ids:
        mine = [n for n in by_job.get(job_id, ()) if _is_job_file(job_id, n)]
        # A sweep killed after removing a done job's files and before releasing its lock left the
        # lock file alone: taken and released below, it goes too.
        if not mine and job_id + ".lock" not in by_job.get(job_id, ()):
            continue
        try:
            fd = sweep_lock.try_lock_job(out_dir, job_id)
        except OSError:
            continue
        if fd is None:
            continue
        try:
            remove_files(out_dir, job_id, mine)
        finally:
            sweep_lock.release_job(out_dir, job_id, fd)
