"""Which `shellcontract` executable a sweep runs (docs/design/sweeps.md, "Workers"): the one
given, the one built or installed with this package, or one on PATH of this package's version;
and a worker's own, checked against the sweep's version. Imports nothing of the compiled core.
"""

import os
import shutil
import subprocess


def _layout():
    """The generated module of a built or installed package (python/CMakeLists.txt): the CLI's
    path from this folder and the version; None in the source tree."""
    try:
        from . import _layout as layout
    except ImportError:
        return None
    return layout


def _executable(path):
    return os.path.abspath(path) if os.path.isfile(path) and os.access(path, os.X_OK) else None


def find_cli(given=None):
    """The `shellcontract` executable here: `given` (--cli) alone when given, else
    $SHELLCONTRACT_CLI alone when set (not empty): a path the user named is never replaced by
    another executable, so either is None when it is not an executable file (before, a mistyped
    $SHELLCONTRACT_CLI was passed over for the build tree's, whose results carry the same version).
    Else the one built or installed with this package (<build>/shellcontract,
    <prefix>/bin/shellcontract), then PATH, where one of another version than this package's is
    passed over (a distribution's beside a newer install); None if none is an executable file."""
    if given is not None:
        return _executable(given)
    if os.environ.get("SHELLCONTRACT_CLI"):
        return _executable(os.environ["SHELLCONTRACT_CLI"])
    here = os.path.dirname(os.path.abspath(__file__))
    layout = _layout()
    built = _executable(os.path.join(here, layout.CLI_FROM_PACKAGE)) if layout else None
    if built:
        return built
    c = shutil.which("shellcontract")
    if c and (layout is None or _release_of(_version_of(c)) == layout.VERSION):
        return os.path.abspath(c)
    if c:
        global PASSED_OVER
        PASSED_OVER = "; passed over {} on PATH: {}, not this package's {}".format(
            c, _version_of(c), layout.VERSION)
    return None


def not_found(given=None):
    """Why find_cli(given) found nothing, for the sweep's message (bad usage)."""
    if given is not None:
        return "--cli {}: not an executable file".format(given)
    if os.environ.get("SHELLCONTRACT_CLI"):
        return ("SHELLCONTRACT_CLI={}: not an executable file (no other executable is taken "
                "instead: correct it, or unset it)".format(os.environ["SHELLCONTRACT_CLI"]))
    return ("cannot find the shellcontract executable (--cli PATH or SHELLCONTRACT_CLI){}".format(
        PASSED_OVER))


PASSED_OVER = ""  # find_cli's note on a PATH executable of another version


def _release_of(version):
    """The release in `--version`'s text: "0.2.0" of "shellcontract 0.2.0+g0123456789ab (avx2
    kernels)" (the build and kernels after it are the job ids' to tell apart); None if not so."""
    words = (version or "").split()
    return words[1].split("+")[0] if len(words) >= 2 and words[0] == "shellcontract" else None


def _version_of(cli):
    try:
        return cli_version(cli)
    except (OSError, subprocess.SubprocessError):
        return None


_VERSIONS = {}  # (path, mtime, size) -> the executable's --version


def cli_version(cli):
    """`cli --version`, asked once per executable file (a replaced file is asked again)."""
    st = os.stat(cli)
    key = (cli, st.st_mtime_ns, st.st_size)
    if key not in _VERSIONS:
        out = subprocess.run([cli, "--version"], capture_output=True, text=True, check=True,
                             timeout=60)
        _VERSIONS[key] = out.stdout.strip()
    return _VERSIONS[key]


class WorkerError(RuntimeError):
    """A worker that cannot run the sweep's jobs (no executable, another version)."""


def worker_cli(client_cli, version, own=True):
    """The executable a worker of an existing cluster runs. `own`: its own (find_cli: its
    $SHELLCONTRACT_CLI, the build tree of its package, its PATH), else the client's path where
    that exists on the worker too; not `own` (the sweep's --cli): the client's path. Its version
    must be the sweep's (the job ids and checkpoints name it). Raises WorkerError saying what is
    wrong."""
    named = os.environ.get("SHELLCONTRACT_CLI")
    if own and named and _executable(named) is None:
        raise WorkerError("its " + not_found())  # not replaced by the client's path either
    cli = find_cli() if own else None
    if cli is None and client_cli and os.path.isfile(client_cli) and os.access(client_cli, os.X_OK):
        cli = client_cli
    if cli is None:
        raise WorkerError(
            "no shellcontract executable on this worker (its SHELLCONTRACT_CLI, its PATH, the "
            "client's {})".format(client_cli) if own else
            "no executable {} on this worker (--cli)".format(client_cli))
    try:
        found = cli_version(cli)
    except (OSError, subprocess.SubprocessError) as e:
        raise WorkerError("{} --version failed ({})".format(cli, e))
    if version is not None and found != version:
        raise WorkerError("{} is version {}, the sweep's is {}".format(cli, found, version))
    return cli


def describe_worker(client_cli, version, own=True):
    """For the sweep's check of an existing cluster's workers before anything runs (Client.run):
    (the executable this worker runs, None) or (None, what is wrong)."""
    try:
        return worker_cli(client_cli, version, own), None
    except WorkerError as e:
        return None, str(e)
