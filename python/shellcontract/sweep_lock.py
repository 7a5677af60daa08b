"""The sweep's locks in DIR/.work (docs/design/sweeps.md, "Jobs"): one per attempt's working
folder, and one per job, held while an attempt of the job runs, so that a second attempt (the same
sweep run twice at once, a rerun while an earlier cluster's jobs still run, Dask's reschedule of a
lost worker's task while its run still saves) knows the job is running and does not start it.

Each lock is `flock` on a file, taken by the process that runs the job and inherited by the job's
run: the kernel releases it when both are gone, whatever ends them. The lock file is removed by
its holder while still locked; a process that locked a file removed meanwhile tries again, so the
lock counts only on the file at the path.
"""

import fcntl
import os
import re
import shutil
import time
import uuid


def same_file(fd, path):
    try:
        a, b = os.fstat(fd), os.stat(path)
    except OSError:
        return False
    return (a.st_dev, a.st_ino) == (b.st_dev, b.st_ino)


# ------------------------------------------------------------------------------------ the job

def job_lock_path(out_dir, job_id):
    """Beside the job's checkpoint, which the lock covers; not a name the tool's files take (its
    own lock is .<id>.ckpt.lock, its temporaries .<id>.ckpt.tmp.*)."""
    return os.path.join(out_dir, ".work", "checkpoints", job_id + ".lock")


def try_lock_job(out_dir, job_id):
    """The job's lock, taken: its file's descriptor (unlocked where the file system has no locks,
    as the tool's own lock goes on without one); None when another attempt holds it."""
    path = job_lock_path(out_dir, job_id)
    for _ in range(100):
        fd = os.open(path, os.O_RDWR | os.O_CREAT | os.O_NOFOLLOW, 0o644)
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            os.close(fd)
            return None
        except OSError:
            return fd  # no locks here
        if same_file(fd, path):
            return fd
        os.close(fd)  # its holder removed it between the open and the lock: once more
    return None


def lock_job(out_dir, job_id, deadline, stopped=lambda: False):
    """The job's lock, waiting for it until the time.monotonic() `deadline` (an attempt that
    was stopped saves and ends within the grace the sweep gives it); None if it is still held
    then, or `stopped()` turns true meanwhile."""
    while True:
        fd = try_lock_job(out_dir, job_id)
        if fd is not None:
            return fd
        if stopped() or time.monotonic() >= deadline:
            return None
        time.sleep(0.2)


def release_job(out_dir, job_id, fd):
    try:
        os.remove(job_lock_path(out_dir, job_id))
    except OSError:
        pass
    os.close(fd)


# ------------------------------------------------------------------------------- the attempts

# An attempt's working folder DIR/.work/<id>.<random>/ (and <id>.<random>.old, an earlier outcome
# being replaced) is in use while DIR/.work/<id>.<random>.lock is locked: by run_job and by the
# job's process, which inherits the lock. A sweep killed with SIGKILL leaves its attempts' folders
# behind with their locks released; the next sweep removes them (clean_stale_attempts).
_ATTEMPT = re.compile(r"^([0-9a-f]{16}\.[0-9a-f]{8})(\.old|\.lock)?$")


def lock_attempt(work_root, job_id):
    """A new attempt's name and its lock file's descriptor, locked (or unlocked where the file
    system has no locks: then no sweep ever takes its folder for stale)."""
    while True:
        name = "{}.{}".format(job_id, uuid.uuid4().hex[:8])
        path = os.path.join(work_root, name + ".lock")
        try:
            fd = os.open(path, os.O_RDWR | os.O_CREAT | os.O_EXCL, 0o644)
        except FileExistsError:
            continue
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            pass  # a cleaner holds it for a moment, and removes it: another name
        except OSError:
            return name, fd  # no locks here
        else:
            # A cleaner may have locked and removed the new file before this lock: the lock
            # counts only if it is on the file at the path.
            if same_file(fd, path):
                return name, fd
        os.close(fd)


def release_attempt(work_root, name, fd):
    try:
        os.remove(os.path.join(work_root, name + ".lock"))
    except OSError:
        pass
    os.close(fd)


def clean_stale_attempts(out_dir):
    """Removes the working folders in DIR/.work of attempts that no process holds any more (a
    sweep or worker killed with SIGKILL); returns how many attempts were removed. An attempt
    whose lock cannot be taken is running (or the file system has no locks) and is left."""
    work_root = os.path.join(out_dir, ".work")
    try:
        names = os.listdir(work_root)
    except OSError:
        return 0
    attempts = {}
    for n in names:
        m = _ATTEMPT.match(n)
        if m:
            attempts.setdefault(m.group(1), set()).add(m.group(2) or "")
    removed = 0
    for name, kinds in sorted(attempts.items()):
        lock = os.path.join(work_root, name + ".lock")
        fd = None
        if ".lock" in kinds:
            try:
                fd = os.open(lock, os.O_RDWR)
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except OSError:  # held (running), gone meanwhile, or no locks here
                if fd is not None:
                    os.close(fd)
                continue
            if not same_file(fd, lock):  # another cleaner removed it meanwhile
                os.close(fd)
                continue
        # Without a lock file the attempt is over: a running one holds its lock file until its
        # folder is gone (lock_attempt makes the lock before the folder).
        for suffix in ("", ".old"):
            shutil.rmtree(os.path.join(work_root, name + suffix), ignore_errors=True)
        if fd is not None:
            release_attempt(work_root, name, fd)
        removed += 1
    return removed
