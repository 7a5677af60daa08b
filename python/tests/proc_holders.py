"""Which processes hold a file open, from /proc (Linux): for the failure messages of tests whose
files a process may still hold."""

import os


def lock_holders(work):
    """(pid, lock file, command line) of the processes with a descriptor on one of the lock files
    in `work`. test_sweep_killed_and_run_again_redoes_no_finished_job failed once under load: a
    killed sweep's attempt whose lock was still held when the rerun started, by a process the
    failure did not name; its message now names them."""
    locks = {str(p) for p in work.glob("*.lock")}
    found = []
    for pid in os.listdir("/proc"):
        if not pid.isdigit():
            continue
        try:
            fds = os.listdir("/proc/{}/fd".format(pid))
        except OSError:
            continue
        for fd in fds:
            try:
                target = os.readlink("/proc/{}/fd/{}".format(pid, fd))
            except OSError:
                continue
            if target in locks:
                try:
                    with open("/proc/{}/cmdline".format(pid), "rb") as f:
                        cmd = f.read().replace(b"\0", b" ").decode(errors="replace")[:200]
                except OSError:
                    cmd = "?"
                found.append((int(pid), os.path.basename(target), cmd))
    return found
