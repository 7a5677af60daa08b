"""The Python side's lists of options kept beside the one option table, held to it: the sweep's
PATH_OPTIONS (a file relative to the sweep file, its bytes in the job id) and contract()'s check
that checkpoint= is not a file the run reads. The table is walked (`run --help` names a value that
is a file FILE), so that a new file option left out of a list fails here instead of slipping past
the output check or the job id."""
import re
import subprocess

import pytest

import shellcontract
from shellcontract import sweep_file


def file_options(cli):
    """{Python name: its keywords} of the table's options whose value may be a FILE, as
    `run --help` writes the value ("--regions auto|none|FILE": regions -> ("auto", "none"))."""
    text = subprocess.run([cli, "run", "--help"], capture_output=True, text=True, check=True).stdout
    python_name = {o.cli_name: o.name for o in shellcontract.options()}
    out = {}
    for m in re.finditer(r"^  --([a-z0-9-]+) (\S*FILE\S*)", text, re.M):
        if m.group(1) in python_name:  # -o, --log, --checkpoint ...: the CLI's, not the table's
            out[python_name[m.group(1)]] = tuple(v for v in m.group(2).split("|") if v != "FILE")
    return out


def test_the_sweeps_path_options_are_the_tables_file_options(cli):
    found = file_options(cli)
    assert {"regions", "region_weights"} <= set(found), found
    assert sweep_file.PATH_OPTIONS == found


def test_no_file_option_may_be_the_checkpoint(cli, tmp_path, ico2):
    v, f = ico2
    for name in file_options(cli):
        path = tmp_path / (name + ".txt")
        path.write_text("0 1 2\n")
        with pytest.raises(ValueError, match="is the file of " + name):
            shellcontract.contract(v, f, frames=2, checkpoint=str(path), **{name: str(path)})
        assert path.read_text() == "0 1 2\n"


def test_the_sweeps_result_neutral_options_are_the_librarys():
    # One list: the options a resumed run may change are those a job's id leaves out.
    names = {o.name for o in shellcontract.options()}
    assert sweep_file.RESULT_NEUTRAL == tuple(shellcontract._core.result_neutral_options())
    assert sweep_file.RESULT_NEUTRAL and set(sweep_file.RESULT_NEUTRAL) <= names
