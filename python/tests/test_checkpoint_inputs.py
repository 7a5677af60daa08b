"""contract()'s checkpoints and the files around them: a face list or weights changed between
the checkpoint and resume= is refused (by file, or as arrays given again); checkpoint= is checked
before the run; a folder given as resume= is named as one; the CLI says to give INPUT for a
checkpoint of arrays. Each test failed before its fix as its docstring says."""
import subprocess

import numpy as np
import pytest

import shellcontract

OPTIONS = dict(frames=10, pressure=0)


def stop_at(frame):
    return lambda f, v, m: f < frame


def checkpointed(v, f, path, **options):
    """A run stopped at frame 4 with its checkpoint there."""
    r = shellcontract.contract(v, f, callback=stop_at(4), checkpoint=path, checkpoint_every=4,
                               **dict(OPTIONS, **options))
    assert r.status == "cancelled" and r.summary["frames_run"] == 4
    return r


def test_a_face_list_edited_since_the_checkpoint_is_refused_naming_it(tmp_path, ico2):
    """Before: resumed with the edited regions, silently."""
    v, f = ico2
    reg = tmp_path / "reg.txt"
    reg.write_text("0 1 2 3 4\n")
    ckpt = str(tmp_path / "c.ckpt")
    checkpointed(v, f, ckpt, regions=str(reg))
    reg.write_text("40 41 42 43 44\n")
    with pytest.raises(ValueError, match="another input: regions .*reg.txt has changed"):
        shellcontract.contract(v, f, resume=ckpt)
    reg.write_text("0 1 2 3 4\n")
    whole = shellcontract.contract(v, f, regions=str(reg), **OPTIONS)
    resumed = shellcontract.contract(v, f, resume=ckpt)
    np.testing.assert_array_equal(resumed.vertices, whole.vertices)


def test_regions_given_as_arrays_are_compared_by_their_faces(tmp_path, ico2):
    """Before: another set of arrays was refused only for its temporary file's path (and the same
    arrays too: every call wrote a new temporary file), with a message naming that file."""
    v, f = ico2
    ckpt = str(tmp_path / "c.ckpt")
    regions = [np.array([4, 0, 2]), np.array([40, 41])]
    checkpointed(v, f, ckpt, regions=regions)
    whole = shellcontract.contract(v, f, regions=regions, **OPTIONS)
    # The same regions, listed in another order within each: the same run.
    again = shellcontract.contract(v, f, resume=ckpt, regions=[[0, 2, 4], [41, 40]])
    np.testing.assert_array_equal(again.vertices, whole.vertices)
    with pytest.raises(ValueError, match="the regions given as arrays are not those its run was given"):
        shellcontract.contract(v, f, resume=ckpt, regions=[[0, 2, 4], [41, 42]])
    with pytest.raises(ValueError, match="regions were given as arrays .*give the same regions again"):
        shellcontract.contract(v, f, resume=ckpt)


def test_weights_given_as_arrays_are_compared(tmp_path, ico2):
    """Before: other weights were accepted (and resume= without them was refused as
    'region_weights: expected a file name')."""
    v, f = ico2
    ckpt = str(tmp_path / "c.ckpt")
    w = np.zeros(len(v))
    w[:5] = 1.0
    checkpointed(v, f, ckpt, region_weights=w)
    shellcontract.contract(v, f, resume=ckpt, region_weights=w.copy())
    w[2] = 0.5
    with pytest.raises(ValueError, match="the region_weights given as arrays are not those"):
        shellcontract.contract(v, f, resume=ckpt, region_weights=w)
    with pytest.raises(ValueError, match="region_weights were given as arrays"):
        shellcontract.contract(v, f, resume=ckpt)


def test_the_checkpoint_path_is_checked_before_the_run(tmp_path, ico2):
    """Before: the run went on to its first save (here the stop at frame 12), and only then
    raised "cannot write ... the folder does not exist", the result lost."""
    v, f = ico2
    frames_seen = []

    def callback(frame, vv, m):
        frames_seen.append(frame)
        return frame < 12
    with pytest.raises(ValueError, match="checkpoint '/nonexistent/c.ckpt': the folder '/nonexistent' does not exist"):
        shellcontract.contract(v, f, frames=30, checkpoint="/nonexistent/c.ckpt", callback=callback)
    with pytest.raises(ValueError, match="is a folder, not a file"):
        shellcontract.contract(v, f, frames=30, checkpoint=tmp_path, callback=callback)
    reg = tmp_path / "reg.txt"
    reg.write_text("0 1 2\n")
    with pytest.raises(ValueError, match="is the file of regions"):
        shellcontract.contract(v, f, frames=30, regions=reg, checkpoint=reg, callback=callback)
    assert frames_seen == []
    assert reg.read_text() == "0 1 2\n"


def test_a_folder_as_resume_is_named_as_a_folder(tmp_path, ico2):
    """Before: RuntimeError 'basic_filebuf::underflow error reading the file: Is a directory'."""
    v, f = ico2
    with pytest.raises(ValueError, match="checkpoint .*: cannot open file: it is a folder"):
        shellcontract.contract(v, f, resume=tmp_path)


def test_the_cli_says_to_give_input_for_a_checkpoint_of_arrays(cli, tmp_path, ico2, mesh_dir):
    """Before: '<arrays>: cannot open file: no such file'."""
    v, f = ico2
    ckpt = tmp_path / "c.ckpt"
    checkpointed(v, f, ckpt)
    r = subprocess.run([cli, "run", "--resume", str(ckpt), "-o", str(tmp_path / "x.off")],
                       capture_output=True, text=True)
    assert r.returncode == 1, r.stderr
    assert "given as arrays (Python)" in r.stderr and "shellcontract run INPUT --resume" in r.stderr
    r = subprocess.run([cli, "run", str(mesh_dir / "ico2.off"), "--resume", str(ckpt), "-o",
                        str(tmp_path / "x.off"), "-q"], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr


def test_resuming_with_other_options_names_them_as_python_does(tmp_path, ico2):
    """Before: 'other options: --frames 11 (the checkpoint's: 10)', the CLI's spelling."""
    v, f = ico2
    path = str(tmp_path / "c.ckpt")
    checkpointed(v, f, path)
    with pytest.raises(ValueError) as e:
        shellcontract.contract(v, f, resume=path, **dict(OPTIONS, frames=11, target_volume=0.5))
    text = str(e.value)
    assert "frames 11 (the checkpoint's: 10)" in text and "target_volume 0.5" in text, text
    assert "--" not in text, text
