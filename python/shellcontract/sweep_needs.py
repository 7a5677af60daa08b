"""The files a sweep's mesh needs besides itself: an OBJ's material libraries and the images they
name, a PLY's texture files, a glTF's external buffers and images (docs/design/output-safety.md,
"Files the input needs"). The sweep writes its tables by its own renames, so sweep_written.py
refuses a table over one of these files: a results.csv written where the OBJ's mtllib points
destroys the user's materials, though it is not the mesh itself. A file named but missing is
listed too (a table that created it would give the mesh a library it did not have).

The list is the library's own (input_dependencies, shellcontract/output_files.hpp), the one the
commands' output check holds, so the sweep cannot drift from it."""

import os

from . import _core


def needed_files(path):
    """(absolute path, what it is to the mesh) of each file the mesh file `path` needs, by its
    extension; [] for OFF and STL, and for a file that cannot be read (its reader refuses it
    before any job runs)."""
    try:
        found = _core.input_dependencies(os.fspath(path))
    except (OSError, ValueError, RuntimeError):
        return []
    return [(os.path.abspath(p), role) for p, role in found]
