"""A file that cannot be read or written raises the OSError that Python's own open() raises for
it (FileNotFoundError, IsADirectoryError, ...), with errno and filename, and is a ValueError too
(what these errors were before: shellcontract.FileError); a file that is read but refused for its
content stays a plain ValueError. Before, every one of them was a plain ValueError, so
`except FileNotFoundError` / `except OSError` caught none.

The expected class and errno are those of Python's open() on the same path, an oracle
independent of the library."""
import errno
import os
import pickle

import numpy as np
import pytest

import shellcontract as sc


def open_error(path, mode):
    """The OSError Python's open(path, mode) raises (None if it opens)."""
    try:
        with open(path, mode):
            pass
    except OSError as e:
        return e
    return None


def check_like_open(error, path, mode):
    """`error` is what open(path, mode) raises, as a shellcontract.FileError."""
    expected = open_error(path, mode)
    assert expected is not None
    assert type(expected) in type(error).__mro__, (type(error), type(expected))
    assert isinstance(error, sc.FileError) and isinstance(error, ValueError)
    assert error.errno == expected.errno
    assert error.filename == os.fspath(path)
    # The library's message, as the CLI prints it, is str() and strerror.
    assert str(error) == error.strerror
    assert os.fspath(path) in str(error)


def test_read_mesh_of_a_missing_file_is_file_not_found(tmp_path):
    path = tmp_path / "missing.off"
    with pytest.raises(FileNotFoundError) as info:
        sc.read_mesh(path)
    check_like_open(info.value, path, "rb")
    assert info.value.errno == errno.ENOENT
    assert str(info.value) == "{}: cannot open file: no such file".format(path)
    # Picklable, as Python's own OSErrors (a worker process hands its error back).
    copy = pickle.loads(pickle.dumps(info.value))
    assert type(copy) is type(info.value) and str(copy) == str(info.value)
    assert copy.errno == errno.ENOENT and copy.filename == str(path)


def test_read_mesh_of_a_folder_is_a_directory_error(tmp_path):
    folder = tmp_path / "looks_like.off"
    folder.mkdir()
    for path in (folder, tmp_path):  # with a mesh's extension, and without
        with pytest.raises(IsADirectoryError) as info:
            sc.read_mesh(path)
        check_like_open(info.value, path, "rb")


def test_read_mesh_under_a_file_is_not_a_directory_error(tmp_path):
    (tmp_path / "file").write_text("x")
    path = tmp_path / "file" / "mesh.off"
    with pytest.raises(NotADirectoryError) as info:
        sc.read_mesh(path)
    check_like_open(info.value, path, "rb")


@pytest.mark.skipif(os.geteuid() == 0, reason="root reads a file whatever its mode")
def test_read_mesh_of_an_unreadable_file_is_a_permission_error(tmp_path, mesh_dir):
    path = tmp_path / "locked.off"
    path.write_bytes((mesh_dir / "ico1.off").read_bytes())
    path.chmod(0)
    with pytest.raises(PermissionError) as info:
        sc.read_mesh(path)
    check_like_open(info.value, path, "rb")


def test_only_file_system_failures_are_oserrors(tmp_path):
    """A file read but refused for its content is a ValueError, not an OSError; a file that
    cannot be opened is an OSError."""
    bad = tmp_path / "bad.off"
    bad.write_text("OFF\n3 1 0\n0 0 0\n1 0 0\n")  # ends before its vertices do
    with pytest.raises(ValueError) as info:
        sc.read_mesh(bad)
    assert not isinstance(info.value, OSError), type(info.value)
    with pytest.raises(OSError):
        sc.read_mesh(tmp_path / "gone.off")


def test_write_mesh_into_a_missing_folder_is_file_not_found(tmp_path, ico2):
    path = tmp_path / "no_such_folder" / "out.off"
    with pytest.raises(FileNotFoundError) as info:
        sc.write_mesh(path, *ico2)
    check_like_open(info.value, path, "w")
    assert not (tmp_path / "no_such_folder").exists()


def test_write_mesh_onto_a_folder_is_a_directory_error(tmp_path, ico2):
    folder = tmp_path / "out.off"
    folder.mkdir()
    with pytest.raises(IsADirectoryError) as info:
        sc.write_mesh(folder, *ico2)
    check_like_open(info.value, folder, "w")


def test_write_mesh_under_a_file_is_not_a_directory_error(tmp_path, ico2):
    (tmp_path / "file").write_text("x")
    path = tmp_path / "file" / "out.off"
    with pytest.raises(NotADirectoryError) as info:
        sc.write_mesh(path, *ico2)
    check_like_open(info.value, path, "w")


def read_only_target(tmp_path):
    """A file name in a folder this process may not create files in: a folder of mode 0555 for
    a user; for root, whom modes do not stop, /sys where its open() is refused, else None."""
    if os.geteuid() != 0:
        folder = tmp_path / "read_only"
        folder.mkdir()
        folder.chmod(0o555)
        return folder / "out.off"
    path = "/sys/shellcontract-test.off"
    return path if isinstance(open_error(path, "w"), PermissionError) else None


def test_write_mesh_into_a_read_only_folder_is_a_permission_error(tmp_path, ico2):
    path = read_only_target(tmp_path)
    if path is None:
        pytest.skip("no folder here refuses root's files")
    try:
        with pytest.raises(PermissionError) as info:
            sc.write_mesh(path, *ico2)
        check_like_open(info.value, path, "w")
    finally:
        if os.geteuid() != 0:
            (tmp_path / "read_only").chmod(0o755)


def test_contract_checkpoint_into_a_missing_folder_is_file_not_found(tmp_path, ico2):
    path = tmp_path / "no_such_folder" / "run.ckpt"
    with pytest.raises(FileNotFoundError) as info:
        sc.contract(*ico2, frames=1, checkpoint=path)
    assert info.value.errno == errno.ENOENT and info.value.filename == str(path)
    assert isinstance(info.value, ValueError)
    assert "does not exist" in str(info.value)


def test_contract_checkpoint_onto_a_folder_is_a_directory_error(tmp_path, ico2):
    with pytest.raises(IsADirectoryError) as info:
        sc.contract(*ico2, frames=1, checkpoint=tmp_path)
    assert info.value.errno == errno.EISDIR and info.value.filename == str(tmp_path)


def test_contract_resume_from_a_missing_checkpoint_is_file_not_found(tmp_path, ico2):
    path = tmp_path / "missing.ckpt"
    with pytest.raises(FileNotFoundError) as info:
        sc.contract(*ico2, frames=1, resume=path)
    check_like_open(info.value, path, "rb")
    assert str(info.value).startswith("checkpoint {}: cannot open file".format(path))


@pytest.mark.parametrize("option", ["regions", "region_weights"])
def test_contract_of_a_missing_regions_or_weights_file_is_file_not_found(tmp_path, ico2, option):
    path = tmp_path / "missing.txt"
    with pytest.raises(FileNotFoundError) as info:
        sc.contract(*ico2, frames=1, **{option: path})
    check_like_open(info.value, path, "rb")


@pytest.mark.parametrize("option", ["regions", "region_weights"])
def test_contract_of_a_folder_as_regions_or_weights_file_is_a_directory_error(tmp_path, ico2, option):
    # The weight file was read by a stream that opened the folder and failed later ("read error
    # after line 0", a plain ValueError); both are now refused by name before anything is read.
    with pytest.raises(IsADirectoryError) as info:
        sc.contract(*ico2, frames=1, **{option: tmp_path})
    assert info.value.errno == errno.EISDIR and info.value.filename == str(tmp_path)
    assert "it is a folder" in str(info.value)
