"""Where the object's mesh comes from and how it is placed: a linked or overridden mesh, whose
shape keys would not be saved, and an object transform that is not a uniform scale, which
changes the shape the run makes."""

import os

import numpy as np

from . import runner


def _library_name(library):
    return os.path.basename(library.filepath) or library.name


def library_refusal(obj):
    """Why the run's shape keys would be lost, or ''. Keys written into linked mesh data, or into
    a library override's mesh, play until the file is saved and are gone when it is reopened
    (Blender does not save linked data, and a shape key added to an override is not one of its
    overridable properties), so the run is refused before it starts, as Blender's own shape-key
    operators are."""
    make_local = "make it local first (Object > Relations > Make Local > Selected Objects and Data)"
    if obj.library is not None:
        return "{} is linked from {}: {}".format(obj.name, _library_name(obj.library), make_local)
    mesh = obj.data
    if mesh.library is not None:
        return "the mesh of {} is linked from {}: {}".format(
            obj.name, _library_name(mesh.library), make_local)
    for what, ref, lost in (("the mesh of " + obj.name, mesh.override_library,
                             "the run's shape keys would not be saved"),
                            (obj.name, obj.override_library,
                             "its ShellContract settings and status would not be saved")):
        if ref is not None:
            lib = ref.reference.library if ref.reference is not None else None
            return "{} is a library override{}: {}; {}".format(
                what, " of " + _library_name(lib) if lib is not None else "", lost, make_local)
    return ""


def run_space(obj):
    """The 3x3 map from the mesh's coordinates to those the run is made in, or None for the
    mesh's own. The object's transform (with its parents') applies a linear map L to the mesh;
    where L is not a rotation times a uniform scale, the shape shown is the mesh stretched, and
    a run in mesh coordinates deflates the unstretched shape (a sphere scaled (1, 1, 3) would sink
    3 times as far along z as the sphere with its scale applied). So the run is made on the
    stretch of L's polar decomposition, L = U P with U a rotation (or a mirror) and
    P = sqrt(L^T L) symmetric positive definite: P times the mesh is the shape shown up to U, in
    the object's own axes, and for an object's rotation R and scale S (L = R S) it is S, Blender's
    Apply Scale. Not L itself: the library normalizes by the axis-aligned bounding box, so a
    rotated copy of a mesh (L's rotation) has another diagonal and another result. The result is
    mapped back with P's inverse. P keeps the faces' orientation (its determinant is positive),
    a mirroring L included. A rotation times a uniform scale changes nothing (the run is the
    same, scaled), so the mesh's coordinates are kept as they were."""
    lin = np.array(obj.matrix_world, dtype=np.float64)[:3, :3]
    gram = lin.T @ lin
    mean = np.trace(gram) / 3.0
    flat = runner.AddonError(
        "{} is scaled to 0 along an axis (Object properties > Transform > Scale): its shape "
        "is flat; give it a scale first".format(obj.name))
    if not mean > 0.0:  # scaled to 0 along every axis: nothing is shown
        raise flat
    if np.max(np.abs(gram - mean * np.eye(3))) <= 1e-6 * mean:
        return None
    if abs(np.linalg.det(lin)) <= 1e-9 * mean ** 1.5:
        raise flat
    squares, axes = np.linalg.eigh(gram)  # gram = axes diag(squares) axes^T, squares > 0 here
    return (axes * np.sqrt(np.maximum(squares, 0.0))) @ axes.T


def to_run(space, vertices):
    return vertices if space is None else vertices @ space.T


def from_run(space, vertices):
    if space is None:
        return vertices
    return np.linalg.solve(space, np.asarray(vertices, dtype=np.float64).T).T
