"""An output that is another name (a hard link) of an input or of another output is refused before
any work, through Python as through the CLI (docs/design/output-safety.md: outputs compared by
file identity, src/mesh/output_check.cpp's same_file). contract()'s outputs are its checkpoint and
the two files beside it (FILE.log, FILE.history), its inputs the regions and weights files. The
same path given twice is refused by the name alone; a hard link has another name, and only the
identity of the file finds it: without it, the first save would replace the user's face list or
weights, or one file beside the checkpoint the other."""
import os

import pytest

import shellcontract


def never_called(frame, v, m):
    raise AssertionError("the run started")


@pytest.mark.parametrize("option", ["regions", "region_weights"])
def test_a_checkpoint_that_is_a_hard_link_of_an_input_is_refused(tmp_path, ico2, option):
    v, f = ico2
    text = "0 1 2\n" if option == "regions" else "".join(
        "1\n" if i < 5 else "0\n" for i in range(len(v)))
    given = tmp_path / (option + ".txt")
    given.write_text(text)
    link = tmp_path / "c.ckpt"
    os.link(given, link)
    with pytest.raises(ValueError) as e:
        shellcontract.contract(v, f, frames=8, checkpoint=link, checkpoint_every=2,
                               callback=never_called, **{option: given})
    assert "checkpoint '{}': is the file of {} ('{}'); choose another name".format(
        link, option, given) in str(e.value)
    assert given.read_text() == text and os.path.samefile(given, link)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["c.ckpt", option + ".txt"]


@pytest.mark.parametrize("beside", ["c.ckpt.log", "c.ckpt.history"])
def test_a_file_beside_the_checkpoint_that_is_a_hard_link_of_another_output_is_refused(
        tmp_path, ico2, beside):
    v, f = ico2
    first = tmp_path / "c.ckpt"
    first.write_text("the user's own\n")
    os.link(first, tmp_path / beside)
    what = {"c.ckpt.log": "checkpoint's log", "c.ckpt.history": "checkpoint's volume history"}
    with pytest.raises(ValueError) as e:
        shellcontract.contract(v, f, frames=8, checkpoint=first, checkpoint_every=2,
                               callback=never_called)
    assert "{} '{}': is also the file of checkpoint ('{}'); each output needs its own file".format(
        what[beside], tmp_path / beside, first) in str(e.value)
    assert first.read_text() == "the user's own\n"
    assert os.path.samefile(first, tmp_path / beside)
