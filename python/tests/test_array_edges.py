"""Arrays a numpy user really passes, at the edges (review pyedges): masked arrays (numpy hands on
the values under the mask), a conversion numpy cannot allocate (it crashed the process), Fortran
faces for write_mesh(like=), the CLI's spelling of the options checked in Python, a uint64 face
array of the wrong shape, an object whose __array__ raises, and regions()'s numbers and region_at's
coordinates taken only as contract() takes numbers."""
import os
import subprocess
import sys

import numpy as np
import pytest

import shellcontract


def test_masked_arrays_with_a_masked_element_are_refused(ico2, tmp_path):
    vertices, faces = ico2
    masked_v = np.ma.masked_array(vertices, mask=np.zeros_like(vertices, dtype=bool))
    masked_v.data[3] = 50.0  # what would be used, hidden under the mask
    masked_v.mask[3] = True
    for call in (lambda: shellcontract.check(masked_v, faces),
                 lambda: shellcontract.contract(masked_v, faces, frames=1),
                 lambda: shellcontract.regions(masked_v, faces),
                 lambda: shellcontract.write_mesh(str(tmp_path / "o.off"), masked_v, faces)):
        with pytest.raises(ValueError, match="vertices: a masked array with masked elements"):
            call()
    assert not (tmp_path / "o.off").exists()
    masked_f = np.ma.masked_array(faces, mask=np.zeros_like(faces, dtype=bool))
    masked_f.mask[7, 1] = True
    with pytest.raises(ValueError, match="faces: a masked array with masked elements"):
        shellcontract.check(vertices, masked_f)
    # Labels: a masked entry moved faces between regions (argsort sorts masked entries last).
    labels = np.full(len(faces), -1)
    labels[:10], labels[300:320] = 0, 1
    masked_labels = np.ma.masked_array(labels, mask=np.zeros(len(faces), dtype=bool))
    masked_labels.mask[5] = True
    with pytest.raises(ValueError, match="regions: a masked array with masked elements"):
        shellcontract.contract(vertices, faces, frames=1, regions=masked_labels)
    weights = np.ma.masked_array(np.full(len(vertices), 0.5), mask=np.zeros(len(vertices), dtype=bool))
    weights.mask[3] = True
    with pytest.raises(ValueError, match="region_weights: a masked array with masked elements"):
        shellcontract.contract(vertices, faces, frames=1, region_weights=weights)
    points = np.ma.masked_array([[0.0, 0.0, 1.0], [9.0, 9.0, 9.0]], mask=[[False] * 3, [True] * 3])
    for key in ("region_at", "region-at"):
        with pytest.raises(ValueError, match="region_at: a masked array with masked elements"):
            shellcontract.contract(vertices, faces, frames=1, **{key: points})
        with pytest.raises(ValueError, match="region_at: a masked array with masked elements"):
            shellcontract.regions(vertices, faces, **{key: points})
    # Without a masked element a masked array is its data.
    plain = np.ma.masked_array(vertices)
    assert shellcontract.check(plain, faces)["volume"] == shellcontract.check(vertices, faces)["volume"]


MEMORY_CHILD = r"""
import resource, sys
import numpy as np
import shellcontract
vertices, faces = shellcontract.read_mesh(sys.argv[1])
big = np.zeros((10_000_000, 3), np.float32)  # 229 MiB as float64: more than the headroom
with open("/proc/self/status") as f:
    size = next(int(l.split()[1]) * 1024 for l in f if l.startswith("VmSize:"))
soft, hard = resource.getrlimit(resource.RLIMIT_AS)
resource.setrlimit(resource.RLIMIT_AS, (size + 150 * 2**20, hard))
outcomes = []
for name, call in (("check", lambda: shellcontract.check(big, faces)),
                   ("contract", lambda: shellcontract.contract(big, faces, frames=1)),
                   ("regions", lambda: shellcontract.regions(big, faces))):
    try:
        call()
        outcomes.append(name + " ran")
    except BaseException as e:
        outcomes.append(name + " " + type(e).__name__)
resource.setrlimit(resource.RLIMIT_AS, (soft, hard))
print(";".join(outcomes))
"""


def test_a_conversion_numpy_cannot_allocate_is_a_memory_error(mesh_dir):
    # float32 vertices are converted to float64 by numpy; under an address-space limit that
    # conversion fails. pybind11's ensure() returned null for it and the module dereferenced it:
    # the process died of a segmentation fault.
    child = subprocess.run([sys.executable, "-c", MEMORY_CHILD, os.path.join(mesh_dir, "ico2.off")],
                           capture_output=True, text=True, timeout=120)
    assert child.returncode == 0, child.stderr[-2000:]
    assert child.stdout.strip() == "check MemoryError;contract MemoryError;regions MemoryError", child.stdout


def test_write_like_takes_the_faces_read_in_any_layout(ico2, tmp_path):
    # The faces read_mesh gives, in another memory layout, are the same faces: write_mesh(like=)
    # compared them in memory order and refused them (and read a reversed view past its end).
    source = tmp_path / "ico2.obj"
    shellcontract.write_mesh(str(source), *ico2)
    vertices, faces = shellcontract.read_mesh(str(source))
    for name, given in (("fortran", np.asfortranarray(faces)),
                        ("fortran int32", np.asfortranarray(faces.astype(np.int32))),
                        ("strided", np.repeat(faces, 2, axis=0)[::2]),
                        ("reversed view", faces[::-1].copy()[::-1])):
        assert np.array_equal(given, faces)
        out = tmp_path / (name.replace(" ", "_") + ".obj")
        shellcontract.write_mesh(str(out), 0.5 * vertices, given, like=str(source))
        assert np.allclose(shellcontract.read_mesh(str(out))[0], 0.5 * vertices), name


def test_the_cli_spelling_of_python_checked_options_is_checked_alike(ico2):
    vertices, faces = ico2
    two_d = np.full((len(vertices), 1), 0.5)
    for key in ("region_weights", "region-weights"):
        with pytest.raises(TypeError, match="region_weights: expected one number per vertex"):
            shellcontract.contract(vertices, faces, frames=1, **{key: two_d})
    with pytest.raises(TypeError, match="the same option"):
        shellcontract.contract(vertices, faces, frames=1, region_weights=two_d[:, 0],
                               **{"region-weights": two_d[:, 0]})
    with pytest.raises(ValueError, match="region_strengths: 1 values for 2 regions"):
        shellcontract.contract(vertices, faces, frames=1, regions=[[0, 1], [100]],
                               **{"region-strengths": [0.5]})


def test_uint64_faces_of_the_wrong_shape_are_named_by_their_shape(ico2):
    vertices, faces = ico2
    wrong = faces.T.astype(np.uint64)
    wrong[0, 100] = 999
    with pytest.raises(ValueError, match=r"faces must be an N by 3 array, got shape \(3, "):
        shellcontract.check(vertices, wrong)


def test_an_object_whose_array_conversion_raises_is_named_with_its_reason(ico2):
    vertices, faces = ico2

    class OnAnotherDevice:
        def __array__(self, dtype=None):
            raise RuntimeError("can't convert cuda:0 device type tensor to numpy")

    with pytest.raises(TypeError, match="vertices must be an array-like of numbers.*cuda:0"):
        shellcontract.check(OnAnotherDevice(), faces)
    with pytest.raises(TypeError, match="faces must be an array-like of integers.*cuda:0"):
        shellcontract.check(vertices, OnAnotherDevice())


@pytest.mark.parametrize("option,value", [
    ("contrast", np.array([2.0])), ("max_area_fraction", np.array([[0.1]])),
    ("contrast", np.complex128(2.0)), ("contrast", 2 + 0j), ("min_faces", np.array([3])),
    ("min_faces", np.complex64(3)), ("fit_tolerance", np.float64(0.1) * np.ones(1)),
])
def test_regions_numbers_are_numbers_not_arrays_or_complex(ico2, option, value):
    """Before: a one-element array (its __float__) or a complex (numpy's, imaginary part dropped)
    was taken as the number; contract() refuses both in its own numbers."""
    with pytest.raises(TypeError, match="regions\\(\\) option " + option):
        shellcontract.regions(*ico2, **{option: value})


def test_regions_numbers_as_numpy_scalars_and_zero_d_arrays_still_count(mesh_dir):
    # On bumpy_sphere these values choose regions that other values would not (contrast 3 or
    # min_faces 40 drop one), so a number misread is seen.
    vertices, faces = shellcontract.read_mesh(mesh_dir / "bumpy_sphere.off")
    base = shellcontract.regions(vertices, faces, contrast=2.0, min_faces=3)
    assert len(base) == 2
    assert len(shellcontract.regions(vertices, faces, contrast=3.0, min_faces=3)) != len(base)
    assert len(shellcontract.regions(vertices, faces, contrast=2.0, min_faces=40)) != len(base)
    for contrast, min_faces in ((np.float32(2.0), np.int64(3)), (np.array(2.0), np.array(3)),
                                (2, 3.0)):
        got = shellcontract.regions(vertices, faces, contrast=contrast, min_faces=min_faces)
        assert [list(r) for r in got] == [list(r) for r in base]


@pytest.mark.parametrize("points", [
    (True, 0.0, 1.0), [(0.0, 0.0, 1.0), (0.0, False, 1.0)], np.array([True, False, True]),
    ("0", "0", "1"), np.array(["1e0", "0", " 1 "]), [(0.0, 0.0, 1 + 0j)], np.zeros(3, complex),
    [[(0.0, 0.0, 1.0)]],
])
def test_region_at_coordinates_are_real_numbers(ico2, points):
    """Before: numpy's conversion read True as 1 and its own string grammar (" 1 ", "1_0") as
    numbers, so region_at=(True, 0, 1) picked the cap near (1, 0, 1)."""
    with pytest.raises((TypeError, ValueError), match="region_at"):
        shellcontract.regions(*ico2, region_at=points)
    with pytest.raises((TypeError, ValueError), match="region_at"):
        shellcontract.contract(*ico2, frames=1, region_at=points)


def test_region_at_of_ints_floats_and_numpy_numbers_is_taken(ico2):
    vertices, _ = ico2
    top = tuple(float(c) for c in vertices[np.argmax(vertices[:, 2])])
    base = shellcontract.regions(*ico2, region_at=[top])
    for points in (np.array([top]), [tuple(np.float32(c) for c in top)], np.array(top)):
        got = shellcontract.regions(*ico2, region_at=points)
        assert [list(r) for r in got] == [list(r) for r in base]
