"""Compatibility shims for the Blender the add-on runs in."""

import numpy


def restore_numpy_bool():
    """Gives numpy back its ``numpy.bool`` alias when it lacks it.

    numpy 1.24 removed the alias (deprecated since 1.20), and Debian's Blender 3.4 glTF importer
    still uses ``np.bool`` (io_scene_gltf2/blender/imp/gltf2_blender_mesh.py), so importing any
    .glb, the CLI's --gltf animation included, fails with AttributeError. ``numpy.bool`` was
    exactly the builtin ``bool``; setting it back changes nothing for code that does not use it.
    Returns True when the alias was added.
    """
    if "bool" in vars(numpy):
        return False
    numpy.bool = bool
    return True
