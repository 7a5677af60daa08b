"""A file that cannot be read or written raises the OSError that Python's own open() raises for
it (FileNotFoundError, IsADirectoryError, ...), with errno and filename, and is a ValueError too
(what these errors were before: shellcontract.FileError); a file that is read but refused for its
content stays a plain ValueError. Before, every one of them was a plain ValueError, so
`except FileNotFoundError` / `except OSError` caught none.

The expected class and errno are those of Python's open() on the same path, an oracle
independent of the library."""
import errno
import os
import pathlib
import pickle
import shutil
import tempfile
import traceback

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


def check_like_open(error, path, mode, named=True):
    """`error` is what open(path, mode) raises, as a shellcontract.FileError; `named`: its
    message names the path."""
    expected = open_error(path, mode)
    assert expected is not None
    assert type(expected) in type(error).__mro__, (type(error), type(expected))
    assert isinstance(error, sc.FileError) and isinstance(error, ValueError)
    assert error.errno == expected.errno
    assert error.filename == os.fspath(path)
    # The library's message, as the CLI prints it, is str() and strerror.
    assert str(error) == error.strerror
    if named:
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


def as_a_user(check):
    """Runs `check()` where file modes apply: in this process for a user; for root, whom modes do
    not stop (a plain skip would drop the test from the CI, which runs as root), in a forked child
    that becomes the user nobody first. The library is loaded already, so nobody need read only
    the files the check opens. A failure in the child fails the test with its traceback."""
    if os.geteuid() != 0:
        check()
        return
    read_end, write_end = os.pipe()
    pid = os.fork()
    if pid == 0:
        status = 1
        try:
            os.close(read_end)
            os.setgroups([])
            os.setresgid(65534, 65534, 65534)
            os.setresuid(65534, 65534, 65534)
            check()
            status = 0
        except BaseException:
            os.write(write_end, traceback.format_exc().encode())
        finally:
            os._exit(status)
    os.close(write_end)
    with os.fdopen(read_end, "rb") as pipe:
        report = pipe.read().decode()
    _, status = os.waitpid(pid, 0)
    assert os.waitstatus_to_exitcode(status) == 0, report


def folder_a_user_reaches(tmp_path):
    """A folder every user may enter: pytest's tmp_path lies under a folder of mode 0700 (as root,
    nobody's open() would be refused there for the path, not for the file's mode)."""
    folder = pathlib.Path(tempfile.mkdtemp(prefix="shellcontract-modes-"))
    folder.chmod(0o755)
    return folder


def test_read_mesh_of_an_unreadable_file_is_a_permission_error(tmp_path, mesh_dir):
    folder = folder_a_user_reaches(tmp_path)
    try:
        path = folder / "locked.off"
        path.write_bytes((mesh_dir / "ico1.off").read_bytes())
        path.chmod(0)
        (folder / "open.off").write_bytes(path.read_bytes())
        (folder / "open.off").chmod(0o644)

        def check():
            sc.read_mesh(folder / "open.off")  # the folder is reached: the mode refuses the file
            with pytest.raises(PermissionError) as info:
                sc.read_mesh(path)
            check_like_open(info.value, path, "rb")

        as_a_user(check)
    finally:
        shutil.rmtree(folder)


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


# A device, a FIFO or a socket is refused for what it is: open() would take it (and block on a
# FIFO), so no errno says why. It is a FileError (OSError and ValueError) with errno None and
# the path as filename, as Python's shutil.copyfile refuses a FIFO (SpecialFileError, an OSError
# without an errno). Before, each was a plain ValueError.

def special_files(tmp_path):
    """A device, a FIFO and a socket, each with a mesh's extension where it can be made."""
    import socket
    fifo = tmp_path / "fifo.off"
    os.mkfifo(fifo)
    sock = tmp_path / "socket.off"
    server = socket.socket(socket.AF_UNIX)
    server.bind(str(sock))
    return server, {"device": "/dev/null", "FIFO": fifo, "socket": sock}


def check_special(error, path, kind):
    assert type(error) is sc.FileError, type(error)
    assert isinstance(error, OSError) and isinstance(error, ValueError)
    assert error.errno is None
    assert error.filename == os.fspath(path)
    assert str(error) == error.strerror
    assert "not a regular file" in str(error) and kind in str(error)


@pytest.fixture
def specials(tmp_path):
    server, paths = special_files(tmp_path)
    yield paths
    server.close()


def test_read_mesh_of_a_device_fifo_or_socket_is_a_file_error_without_errno(specials):
    for kind, path in specials.items():
        with pytest.raises(sc.FileError) as info:
            sc.read_mesh(path)
        check_special(info.value, path, kind)
        what = {"device": "a device", "FIFO": "a FIFO (named pipe)", "socket": "a socket"}[kind]
        # The message is the CLI's, unchanged.
        assert str(info.value) == "{}: not a regular file: it is {}; inputs must be regular " \
            "files".format(path, what)


@pytest.mark.parametrize("option", ["regions", "region_weights"])
def test_contract_of_a_device_or_fifo_as_regions_or_weights_is_a_file_error(specials, ico2, option):
    for kind in ("device", "FIFO"):
        path = specials[kind]
        with pytest.raises(sc.FileError) as info:
            sc.contract(*ico2, frames=1, **{option: path})
        check_special(info.value, path, kind)


def test_contract_resume_from_a_fifo_is_a_file_error(specials, ico2):
    with pytest.raises(sc.FileError) as info:
        sc.contract(*ico2, frames=1, resume=specials["FIFO"])
    check_special(info.value, specials["FIFO"], "FIFO")
    assert str(info.value).startswith("checkpoint {}:".format(specials["FIFO"]))


def test_write_mesh_onto_a_fifo_or_socket_is_a_file_error_without_errno(specials, ico2):
    for kind in ("FIFO", "socket"):
        path = specials[kind]
        with pytest.raises(sc.FileError) as info:
            sc.write_mesh(path, *ico2)
        assert type(info.value) is sc.FileError and info.value.errno is None
        assert info.value.filename == str(path)
        assert str(info.value) == ("cannot write '{}': it exists and is not a regular file (a "
                                   "device, FIFO or socket is never replaced)".format(path))
    import stat
    assert stat.S_ISFIFO(os.stat(specials["FIFO"]).st_mode)  # never replaced


SPECIAL_OUTPUT = ("cannot write '{}': it exists and is not a regular file (a device, FIFO or "
                  "socket is never replaced)")


def test_write_mesh_onto_a_device_fifo_or_folder_without_extension_is_refused_for_what_it_is(
        tmp_path, ico2):
    """Before: /dev/null, a FIFO or a folder named without a mesh's extension was refused for its
    name ("the file name has no extension", a plain ValueError; for the folder, "it is a folder
    (expected .off, ...)"), not for what it is, as the CLI's check of its outputs refuses it.
    Nothing here opens /dev/null: it is only stat'ed, and with no extension the writer would
    refuse it for the name even without that check."""
    fifo = tmp_path / "fifo"
    os.mkfifo(fifo)
    folder = tmp_path / "folder"
    folder.mkdir()
    for path in ("/dev/null", fifo):
        with pytest.raises(sc.FileError) as info:
            sc.write_mesh(path, *ico2)
        assert type(info.value) is sc.FileError and info.value.errno is None
        assert info.value.filename == str(path)
        assert str(info.value) == SPECIAL_OUTPUT.format(path)
    with pytest.raises(IsADirectoryError) as info:
        sc.write_mesh(folder, *ico2)
    assert info.value.errno == errno.EISDIR and info.value.filename == str(folder)
    assert str(info.value) == "cannot write '{}': it is a folder".format(folder)
    import stat
    assert stat.S_ISFIFO(os.stat(fifo).st_mode) and os.listdir(folder) == []  # never replaced
    assert sorted(os.listdir(tmp_path)) == ["fifo", "folder"]  # no temporary left


def test_write_mesh_like_onto_a_device_fifo_or_folder_is_refused_for_what_it_is(tmp_path, ico2):
    """Before: with like=, a target without the like file's extension was refused for its name
    first ("only an OBJ or PLY file, written to a file of its format", a plain ValueError),
    whatever it was."""
    like = tmp_path / "like.obj"
    sc.write_mesh(like, *ico2)
    v, f = sc.read_mesh(like)
    fifo = tmp_path / "fifo.off"  # another format's extension
    os.mkfifo(fifo)
    folder = tmp_path / "folder"
    folder.mkdir()
    for path in ("/dev/null", fifo):
        with pytest.raises(sc.FileError) as info:
            sc.write_mesh(path, v, f, like=like)
        assert type(info.value) is sc.FileError and info.value.errno is None
        assert info.value.filename == str(path)
        assert str(info.value) == SPECIAL_OUTPUT.format(path)
    with pytest.raises(IsADirectoryError) as info:
        sc.write_mesh(folder, v, f, like=like)
    assert str(info.value) == "cannot write '{}': it is a folder".format(folder)
    assert sorted(os.listdir(tmp_path)) == ["fifo.off", "folder", "like.obj"]


def test_contract_checkpoint_onto_a_fifo_is_a_file_error_without_errno(specials, ico2):
    path = specials["FIFO"]
    with pytest.raises(sc.FileError) as info:
        sc.contract(*ico2, frames=1, checkpoint=path)
    assert type(info.value) is sc.FileError and info.value.errno is None
    assert info.value.filename == str(path)
    assert "exists and is not a regular file" in str(info.value)


def test_a_regions_file_over_its_size_limit_is_a_file_error_efbig(tmp_path, ico2):
    """A face-list file larger than any list of this mesh's faces is refused before it is read
    ("file too large"): EFBIG, the errno the OS gives for a file over a size limit."""
    path = tmp_path / "huge.txt"
    with open(path, "wb") as f:
        f.truncate(64 << 20)  # sparse: no disk used
    with pytest.raises(sc.FileError) as info:
        sc.contract(*ico2, frames=1, regions=path)
    assert type(info.value) is sc.FileError
    assert info.value.errno == errno.EFBIG and info.value.filename == str(path)
    assert str(info.value).startswith("{}: file too large: {} bytes".format(path, 64 << 20))


def test_a_checkpoint_locked_by_another_run_is_a_blocking_io_error(tmp_path, ico2):
    """The lock another run holds is what Python's own flock() refuses with BlockingIOError."""
    import fcntl
    path = tmp_path / "run.ckpt"
    lock = tmp_path / ".run.ckpt.lock"  # the documented lock file
    held = os.open(lock, os.O_RDWR | os.O_CREAT, 0o666)
    other = os.open(lock, os.O_RDWR)
    try:
        fcntl.flock(held, fcntl.LOCK_EX | fcntl.LOCK_NB)
        with pytest.raises(BlockingIOError) as expected:  # the oracle: Python's own flock
            fcntl.flock(other, fcntl.LOCK_EX | fcntl.LOCK_NB)
        with pytest.raises(BlockingIOError) as info:
            sc.contract(*ico2, frames=1, checkpoint=path)
    finally:
        os.close(other)
        os.close(held)
    error = info.value
    assert isinstance(error, sc.FileError) and isinstance(error, ValueError)
    assert error.errno == expected.value.errno
    assert error.filename == str(path)
    assert "another shellcontract run is saving to this checkpoint" in str(error)
    assert str(error) == error.strerror
    copy = pickle.loads(pickle.dumps(error))
    assert type(copy) is type(error) and copy.errno == error.errno


# A glTF whose external buffer cannot be had: the error is about the buffer (its path as
# filename, the errno open() gives for it), where before it was a plain ValueError naming only
# the .gltf. The message stays the CLI's, naming the .gltf and the buffer's URI.

BUFFER = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], dtype="<f4").tobytes() + \
    np.array([0, 1, 2], dtype="<u4").tobytes()


def gltf_with_buffer(path, uri):
    import json
    document = {
        "asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
        "buffers": [{"uri": uri, "byteLength": len(BUFFER)}],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36},
                        {"buffer": 0, "byteOffset": 36, "byteLength": 12}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                       "min": [0, 0, 0], "max": [1, 1, 0]},
                      {"bufferView": 1, "componentType": 5125, "count": 3, "type": "SCALAR"}]}
    path.write_text(json.dumps(document))
    return path


@pytest.mark.parametrize("uri, name", [("nowhere.bin", "nowhere.bin"),
                                       ("no%20where.bin", "no where.bin")])
def test_gltf_with_a_missing_buffer_is_file_not_found_naming_the_buffer(tmp_path, uri, name):
    gltf = gltf_with_buffer(tmp_path / "mesh.gltf", uri)
    with pytest.raises(FileNotFoundError) as info:
        sc.read_mesh(gltf)
    # The message is the CLI's, unchanged: the .gltf and the buffer's URI.
    check_like_open(info.value, tmp_path / name, "rb", named=False)
    assert str(info.value) == "{}: cannot read .gltf: tinygltf: File not found : {}".format(gltf, name)


def test_gltf_with_a_buffer_under_a_file_is_not_a_directory_error(tmp_path):
    (tmp_path / "file").write_text("x")
    gltf = gltf_with_buffer(tmp_path / "mesh.gltf", "file/mesh.bin")
    with pytest.raises(NotADirectoryError) as info:
        sc.read_mesh(gltf)
    check_like_open(info.value, tmp_path / "file" / "mesh.bin", "rb", named=False)


def test_gltf_with_a_folder_as_buffer_is_a_directory_error(tmp_path):
    (tmp_path / "mesh.bin").mkdir()
    gltf = gltf_with_buffer(tmp_path / "mesh.gltf", "mesh.bin")
    with pytest.raises(IsADirectoryError) as info:
        sc.read_mesh(gltf)
    check_like_open(info.value, tmp_path / "mesh.bin", "rb")


def test_gltf_with_an_unreadable_buffer_is_a_permission_error(tmp_path):
    folder = folder_a_user_reaches(tmp_path)
    try:
        (folder / "mesh.bin").write_bytes(BUFFER)
        (folder / "mesh.bin").chmod(0)
        gltf = gltf_with_buffer(folder / "mesh.gltf", "mesh.bin")
        gltf.chmod(0o644)

        def check():
            with pytest.raises(PermissionError) as info:
                sc.read_mesh(gltf)
            check_like_open(info.value, folder / "mesh.bin", "rb")

        as_a_user(check)
    finally:
        shutil.rmtree(folder)


def test_gltf_with_a_fifo_as_buffer_is_a_file_error_naming_the_buffer(tmp_path):
    os.mkfifo(tmp_path / "mesh.bin")
    gltf = gltf_with_buffer(tmp_path / "mesh.gltf", "mesh.bin")
    with pytest.raises(sc.FileError) as info:
        sc.read_mesh(gltf)
    assert type(info.value) is sc.FileError and info.value.errno is None
    assert info.value.filename == str(tmp_path / "mesh.bin")


def test_gltf_with_a_buffer_of_the_wrong_size_stays_a_value_error(tmp_path):
    """A buffer that is read but holds too few bytes is refused for its content: no OSError."""
    (tmp_path / "mesh.bin").write_bytes(BUFFER[:-4])
    gltf = gltf_with_buffer(tmp_path / "mesh.gltf", "mesh.bin")
    with pytest.raises(ValueError) as info:
        sc.read_mesh(gltf)
    assert not isinstance(info.value, OSError), type(info.value)
