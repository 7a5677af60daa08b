"""What became of a sweep's job, from the exit status, summary and messages of its
`shellcontract run` (docs/design/sweeps.md, "Jobs"): its status, and whether the next sweep runs
it again. Imports nothing of the compiled core, as sweep_job.
"""

import re
import signal

# Statuses of an outcome the same run would give again: the job is done. The others (a crash,
# a kill, a timeout) are recorded too but run again by the next sweep of the file.
FINAL_STATUSES = ("ok", "target not reached", "failed", "new self-intersections", "bad input",
                  "bad usage")
EXIT_STATUS = {0: "ok", 1: "bad usage", 2: "bad input", 3: "failed", 4: "new self-intersections",
               5: "target not reached"}
# The CLI's exit code after a signal when it has written its checkpoint (ExitCode::Cancelled).
INTERRUPTED = 130
# A run that ended but could not write an output into the job's folder (a full disk, a quota, an
# I/O error): exit 1, or the run's own 3, 4 or 5 when it failed too, with a summary whose
# `outputs` name the failure, or with no summary (it could not be written either) and the tool
# saying so. The condition is the machine's, not the job's, so the job is not final: the next
# sweep runs it again.
OUTPUT_NOT_WRITTEN = "output not written"
# A run that the system refused a resource before it had a result: no descriptor (the limit of
# open files), no thread, no memory (exit 3, or 1 for a file it could not make, with no summary
# and the tool's message naming it). The machine's condition too, as a kill by the OOM killer: the
# job is not final and its checkpoint is kept. A run that ran out of memory during its frames
# ends itself with a summary: that is the job's "failed".
OUT_OF_RESOURCES = "out of resources"
# The job's checkpoint could not be read (exit 2, the tool naming it with a read error such as
# EIO or EMFILE, not its contents): the machine's condition too. The checkpoint is kept and the
# next sweep tries to resume from it again.
CHECKPOINT_NOT_READ = "checkpoint not read"


def last_lines(path, n=3):
    """The last `n` lines of the file `path` that are not blank, joined by " | " ("" if none)."""
    try:
        with open(path, errors="replace") as f:
            lines = [line.rstrip() for line in f if line.strip()]
    except OSError:
        return ""
    return " | ".join(lines[-n:])


# The tool's words for a resource the system refused (file_error_text's strerror for EMFILE,
# ENFILE and ENOMEM; the CLI's "out of memory"; TBB's and std::thread's refused thread).
_REFUSED_RESOURCE = re.compile(r"Too many open files|Cannot allocate memory|out of memory|"
                               r"pthread_create has failed|Resource temporarily unavailable")
# report_run_end's line before the list of outputs, when one could not be written.
_OUTPUTS_FAILED = "not every output could be written"


def classify(rc, timed_out, summary, messages, tool_lines=()):
    """The job's (status, message) from the run's exit status `rc`, its summary (None: none was
    written), the last lines of its messages and `tool_lines`, the tool's own error lines."""
    if timed_out:
        return "timeout", "stopped after --job-timeout"
    if rc is not None and rc < 0:
        sig = -rc
        if sig == signal.SIGKILL:
            return "killed", ("killed by SIGKILL (out of memory, or the system's OOM killer); "
                              + messages).rstrip("; ")
        name = signal.Signals(sig).name if sig in signal.Signals._value2member_map_ else str(sig)
        return "crashed", ("crashed ({}); {}".format(name, messages)).rstrip("; ")
    if rc == INTERRUPTED:
        return "interrupted", "interrupted (checkpoint written)"
    status = EXIT_STATUS.get(rc, "crashed")
    if status == "ok":
        return status, ""
    outputs = (summary or {}).get("outputs") or {}
    # "--checkpoint" is a note, not an output (a save that failed: the run went on, its result
    # whole).
    failed = ["{}: {}".format(k, v) for k, v in outputs.items()
              if k != "--checkpoint" and not str(v).startswith("written")]
    # The exit code of a run whose output failed is 1, or the run's own when it failed too.
    if rc in (1, 3, 4, 5):
        if failed:
            return OUTPUT_NOT_WRITTEN, "the run ended ({}) but {}".format(
                summary.get("status", "?"), "; ".join(failed))
        if summary is None and any(_OUTPUTS_FAILED in line for line in tool_lines):
            return OUTPUT_NOT_WRITTEN, ("the run ended but its summary and another output "
                                        "could not be written: " + messages)
    if rc in (1, 3) and summary is None:
        refused = [line for line in tool_lines if _REFUSED_RESOURCE.search(line)]
        if refused:
            return OUT_OF_RESOURCES, refused[-1]
    failure = (summary or {}).get("failure") or messages
    return status, failure
