"""Shared fixtures: the built CLI and the committed meshes (paths come from CTest's environment,
python/CMakeLists.txt)."""
import os
import pathlib

import pytest

import shellcontract


@pytest.fixture(scope="session")
def cli():
    path = os.environ.get("SHELLCONTRACT_CLI")
    if not path or not os.access(path, os.X_OK):
        pytest.fail("SHELLCONTRACT_CLI must name the built shellcontract executable (set by CTest)")
    return path


@pytest.fixture(scope="session")
def mesh_dir():
    return pathlib.Path(os.environ.get("SHELLCONTRACT_MESH_DIR",
                                       pathlib.Path(__file__).resolve().parents[2] / "meshes"))


@pytest.fixture
def ico2(mesh_dir):
    return shellcontract.read_mesh(mesh_dir / "ico2.off")
