#!/usr/bin/env python3
"""The installed Python package's metadata, as run_consumer.cmake's staged install has it:

    check_dist_info.py SITE VERSION

SITE is the folder the package was installed into (on PYTHONPATH here), VERSION the release.
importlib.metadata must find the distribution "shellcontract" there with that version (the one the
compiled module reports too) and numpy among its requirements; its RECORD must list exactly the
files installed for it, each with its size and SHA-256; and pip, where it is installed, must show
it. Exit status 0, or 1 with what is wrong.
"""

import base64
import hashlib
import importlib.metadata as metadata
import os
import subprocess
import sys


def main(site, version):
    problems = []
    try:
        dist = metadata.distribution("shellcontract")
    except metadata.PackageNotFoundError:
        print("importlib.metadata finds no distribution 'shellcontract' (no dist-info in {})".format(site))
        return 1
    if os.path.realpath(str(dist.locate_file(""))) != os.path.realpath(site):
        problems.append("metadata found in {}, not in {}".format(dist.locate_file(""), site))
    if metadata.version("shellcontract") != version:
        problems.append("importlib.metadata.version: {}, expected {}".format(
            metadata.version("shellcontract"), version))
    import shellcontract
    if shellcontract.__version__.split("+")[0] != version:
        problems.append("shellcontract.__version__ {} is not of release {}".format(
            shellcontract.__version__, version))
    if dist.metadata["Summary"] in (None, ""):
        problems.append("METADATA has no Summary")
    requires = [r.split(";")[0].strip() for r in (dist.requires or []) if "extra ==" not in r]
    if "numpy" not in requires:
        problems.append("Requires-Dist lacks numpy: {}".format(dist.requires))
    if (dist.read_text("INSTALLER") or "").strip() == "":
        problems.append("no INSTALLER")
    # RECORD against what is on disk: the package's folder and the dist-info, nothing more or less.
    recorded = {str(f) for f in (dist.files or [])}
    on_disk = set()
    for top in ("shellcontract", "shellcontract-{}.dist-info".format(version)):
        for folder, dirs, files in os.walk(os.path.join(site, top)):
            dirs[:] = [d for d in dirs if d != "__pycache__"]
            on_disk.update(os.path.relpath(os.path.join(folder, f), site) for f in files)
    for f in sorted(on_disk - recorded):
        problems.append("installed, not in RECORD: {}".format(f))
    for f in sorted(recorded - on_disk):
        problems.append("in RECORD, not installed: {}".format(f))
    # Each file's size and SHA-256 (URL-safe base64, no padding), RECORD's own line excepted.
    for f in dist.files or []:
        if not os.path.exists(f.locate()) or str(f).endswith(".dist-info/RECORD"):
            continue
        with open(f.locate(), "rb") as stream:
            data = stream.read()
        digest = base64.urlsafe_b64encode(hashlib.sha256(data).digest()).rstrip(b"=").decode()
        if f.size != len(data):
            problems.append("RECORD's size of {} is {}, the file's {}".format(f, f.size, len(data)))
        if f.hash is None or (f.hash.mode, f.hash.value) != ("sha256", digest):
            problems.append("RECORD's hash of {} is {}, the file's sha256={}".format(
                f, f.hash and "{}={}".format(f.hash.mode, f.hash.value), digest))
    pip = subprocess.run([sys.executable, "-m", "pip", "--version"], capture_output=True, text=True)
    if pip.returncode != 0:
        print("pip is not installed for {}: `pip show` not checked".format(sys.executable))
    else:
        show = subprocess.run([sys.executable, "-m", "pip", "show", "shellcontract"],
                              capture_output=True, text=True)
        fields = dict(line.split(": ", 1) for line in show.stdout.splitlines() if ": " in line)
        if show.returncode != 0 or fields.get("Version") != version or fields.get("Requires") != "numpy":
            problems.append("pip show shellcontract (exit code {}):\n{}{}".format(
                show.returncode, show.stdout, show.stderr))
    for p in problems:
        print(p)
    if not problems:
        print("shellcontract {} in {}: importlib.metadata, RECORD ({} files) and pip agree".format(
            version, site, len(recorded)))
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1], sys.argv[2]))
