"""contract()'s regions argument: which form a value is read as, and the checks of labels and
face lists (by Python's indices, never naming the temporary face-list file the library reads)."""
import tempfile

import numpy as np
import pytest

import shellcontract


@pytest.fixture(scope="module")
def bumpy(mesh_dir):
    return shellcontract.read_mesh(mesh_dir / "bumpy_sphere.off")


def run(mesh, **options):
    return shellcontract.contract(*mesh, frames=1, pressure=0.0, **options)


def test_an_empty_list_from_regions_is_no_regions_like_auto_finding_none(mesh_dir):
    """Before: the empty list was read as a label array (12 faces, 0 labels)."""
    cube = shellcontract.read_mesh(mesh_dir / "cube.off")
    found = shellcontract.regions(*cube)
    assert found == []
    empty = shellcontract.contract(*cube, regions=found, frames=2)
    auto = shellcontract.contract(*cube, regions="auto", frames=2)
    assert empty.summary["regions"] == auto.summary["regions"] == 0
    assert any("no region" in w for w in empty.summary["warnings"])
    # Named by the argument, not by the temporary file the library reads face lists from.
    assert not any("regions.txt" in w or tempfile.gettempdir() in w for w in empty.summary["warnings"])
    assert (empty.vertices == auto.vertices).all()


def test_one_face_regions_are_regions_not_labels(bumpy):
    """Before: [array([3]), array([7])] was read as two labels."""
    a = run(bumpy, regions=[np.array([3]), np.array([7])])
    b = run(bumpy, regions=[[3], [7]])
    assert a.summary["regions"] == b.summary["regions"] == 2
    assert (a.vertices == b.vertices).all()


def test_labels_and_face_lists_give_the_same_run(bumpy):
    labels = np.full(len(bumpy[1]), -1)
    labels[:10] = 0
    labels[20:30] = 1
    lists = [list(range(10)), list(range(20, 30))]
    runs = [run(bumpy, regions=r) for r in (labels, list(labels), tuple(int(x) for x in labels), lists,
                                             [np.array(r) for r in lists], tuple(lists))]
    assert all(r.summary["regions"] == 2 for r in runs)
    assert all((r.vertices == runs[0].vertices).all() for r in runs)


@pytest.mark.parametrize("value,fragment", [
    (b"auto", "got bytes"),
    ({0: [1, 2]}, "got dict"),
    (3, "got int"),
    (np.array([[1, 2]]), "2-D int64 array"),
    ([0, [1]], r"regions\[1\] = \[1\]"),
    ([[1], 0], r"regions\[1\] = 0"),
    ([[0], "ab"], r"regions\[1\] = 'ab'"),
])
def test_a_value_of_no_documented_form_is_a_type_error_saying_what_regions_takes(bumpy, value, fragment):
    """Before: bytes, a dict or an int went down the label path ("4 labels", "1 labels")."""
    with pytest.raises(TypeError, match="regions: expected 'auto', 'none' or a face-list file") as e:
        run(bumpy, regions=value)
    assert e.match(fragment)


def test_regions_none_is_the_default(bumpy):
    """Before: TypeError (option regions: expected a number, a string or a bool)."""
    assert (run(bumpy, regions=None).vertices == run(bumpy).vertices).all()


@pytest.mark.parametrize("regions,fragment", [
    ([[0, 1, 99999]], r"regions\[0\]: face 99999 is out of range"),
    ([[0, 1], [2, -1]], r"regions\[1\]: face -1 is out of range"),
    ([[0, 1], [5, 1]], r"regions\[1\]: face 1 is also in regions\[0\]"),
    ([[0, 1, 1]], r"regions\[0\]: face 1 is twice"),
    ([[0, 1], [], [5, 6]], r"regions\[1\] is empty"),
    ([np.array([0, 1]), np.array([], dtype=np.int64)], r"regions\[1\] is empty"),
])
def test_bad_face_lists_are_value_errors_naming_the_region_and_face(bumpy, regions, fragment):
    """Before: the library's message named the temporary file (/tmp/.../regions.txt:1), and an
    empty region was dropped, shifting the later regions."""
    with pytest.raises(ValueError, match=fragment) as e:
        run(bumpy, regions=regions)
    assert "regions.txt" not in str(e.value)


def test_an_empty_region_with_strengths_names_the_region(bumpy):
    """Before: "/tmp/.../regions.txt:2: a strength with no face after it"."""
    with pytest.raises(ValueError, match=r"regions\[1\] is empty"):
        run(bumpy, regions=[[0, 1], [], [5, 6]], region_strengths=[1, 1, 1])


@pytest.mark.parametrize("regions,fragment", [
    ([[0, 1, 2.7]], r"regions\[0\]\[2\] = 2.7"),
    ([[0, 1, 2.0]], r"regions\[0\]\[2\] = 2.0"),
    ([[0, float("nan")]], r"regions\[0\]\[1\] = nan"),
    ([[0, True]], r"regions\[0\]\[1\] = True"),
    ([np.array([1.0, 2.0])], r"regions\[0\]: expected a 1-D array of integer face indices"),
    ([0.5, 1], r"regions\[0\] = 0.5"),
])
def test_non_integer_face_indices_are_type_errors(bumpy, regions, fragment):
    """Before: 2.7 was truncated to face 2 and the run went on."""
    with pytest.raises(TypeError, match=fragment):
        run(bumpy, regions=regions)


def test_float_labels_are_refused_whatever_their_value(bumpy):
    """Before: lab + 0.5 turned every -0.5 into region 0 and ran."""
    labels = np.full(len(bumpy[1]), -1)
    labels[:10] = 0
    for value in (labels + 0.5, labels.astype(np.float64)):
        with pytest.raises(TypeError, match="float64 array"):
            run(bumpy, regions=value)


@pytest.mark.parametrize("face,label,fragment", [
    (5, -7, "face 5 has label -7"),
    (5, 10**6, "face 5 has label 1000000"),
    (5, 10**30, "face 5 has label 1000000000000000000000000000000"),
])
def test_labels_out_of_range_are_value_errors_naming_the_face(bumpy, face, label, fragment):
    """Before: -7 was no region; a huge label built a list of that many regions."""
    labels = [-1] * len(bumpy[1])
    labels[face] = label
    with pytest.raises(ValueError, match=fragment):
        run(bumpy, regions=labels)


def test_labels_with_a_gap_or_none_set(bumpy):
    labels = np.full(len(bumpy[1]), -1)
    assert run(bumpy, regions=labels).summary["regions"] == 0
    labels[:10] = 0
    labels[20:30] = 2
    with pytest.raises(ValueError, match="no face has label 1"):
        run(bumpy, regions=labels)


@pytest.mark.parametrize("extra,warned", [({"measure_regions": True}, 0), ({"aniso": "arap"}, 1)])
def test_an_empty_list_warns_as_an_empty_face_list_file_does(mesh_dir, extra, warned):
    """regions=[] runs as "none"; its warning follows the library's for an empty file: none when
    the regions are only measured, and one (the aniso option's) where that option already warns."""
    cube = shellcontract.read_mesh(mesh_dir / "cube.off")
    result = shellcontract.contract(*cube, regions=[], frames=2, **extra)
    assert sum("no region" in w for w in result.summary["warnings"]) == warned, result.summary["warnings"]


def test_the_summary_says_regions_and_weights_came_as_arrays(bumpy):
    # Before: options["regions"] was the deleted temporary file the lists went through, the
    # weights '' as if not given, and the strengths were nowhere.
    v, f = bumpy
    r = shellcontract.contract(v, f, frames=2, regions=shellcontract.regions(v, f),
                               region_strengths=np.array([0.5, 1, 1]))
    assert r.summary["options"]["regions"] == "<3 regions given as arrays>"
    assert r.summary["options"]["region_strengths"] == [0.5, 1.0, 1.0]
    w = shellcontract.contract(v, f, frames=2, region_weights=np.linspace(0, 1, len(v)))
    assert w.summary["options"]["region_weights"] == "<weights given as an array>"


def test_region_weights_none_is_the_default(bumpy):
    # Before: None was read as one NaN weight ("1 weights for 642 vertices").
    v, f = bumpy
    r = shellcontract.contract(v, f, frames=2, region_weights=None)
    assert r.vertices.tolist() == shellcontract.contract(v, f, frames=2).vertices.tolist()


@pytest.mark.parametrize("strengths, fragment", [
    (0.5, "one number per region"), ("0.5,1,1", "one number per region"),
    ([True, False, True], "not bools"), ([[0.5, 1, 1]], "one number per region")])
def test_region_strengths_of_another_shape_are_type_errors_saying_what_they_take(bumpy, strengths, fragment):
    # Before: 0.5 gave "'float' object is not iterable" and "0.5,1,1" was walked by character.
    v, f = bumpy
    with pytest.raises(TypeError, match=fragment):
        shellcontract.contract(v, f, frames=2, regions=shellcontract.regions(v, f), region_strengths=strengths)


@pytest.mark.parametrize("every, error", [(1.5, ValueError), ("x", ValueError), (True, TypeError),
                                          (0, ValueError), (2**40, ValueError)])
def test_checkpoint_every_of_another_kind_says_what_it_takes(bumpy, tmp_path, every, error):
    # Before: pybind11's "Unable to cast Python instance to C++ type"; True was taken as 1 and 0
    # was accepted.
    v, f = bumpy
    with pytest.raises(error, match="checkpoint_every: expected an integer >= 1"):
        shellcontract.contract(v, f, frames=2, checkpoint=str(tmp_path / "c.ckpt"), checkpoint_every=every)


def test_an_empty_file_name_is_refused_as_the_cli_refuses_it(bumpy):
    v, f = bumpy
    for name in ("checkpoint", "resume"):
        with pytest.raises(ValueError, match="{} must not be empty".format(name)):
            shellcontract.contract(v, f, frames=2, **{name: ""})


@pytest.mark.parametrize("empty", [[], np.zeros(0)])
def test_empty_region_weights_are_refused(bumpy, empty):
    # Before: no weights read as no option: the run went on without regions, silently.
    v, f = bumpy
    with pytest.raises(ValueError, match="region_weights: no weights"):
        shellcontract.contract(v, f, frames=2, region_weights=empty)


@pytest.mark.parametrize("weights, error, fragment", [
    # Before: a 2-D array of the right total size was flattened, complex weights lost their
    # imaginary part with only numpy's ComplexWarning, strings were parsed, and an int too large
    # for a float was an OverflowError instead of the documented ValueError.
    (lambda n: np.full((n // 2, 2), 0.5), TypeError, "shape"),
    (lambda n: np.full(n, 0.5 + 0.5j), TypeError, "complex"),
    (lambda n: np.array(["0.5"] * n), TypeError, "expected numbers"),
    (lambda n: np.ones(n, bool), TypeError, "expected numbers"),
    (lambda n: [10 ** 400] + [0.5] * (n - 1), ValueError, "region_weights[0]"),
])
def test_region_weights_that_are_not_one_number_per_vertex_are_refused(bumpy, weights, error, fragment):
    n = len(bumpy[0])
    assert n % 2 == 0
    with pytest.raises(error) as e:
        run(bumpy, region_weights=weights(n))
    assert fragment in str(e.value), str(e.value)


def test_region_strengths_given_as_text_are_refused(bumpy):
    # Before: ["0.5"] passed float() and was taken as 0.5.
    with pytest.raises(TypeError, match=r"region_strengths\[0\] = '0.5' is not a number"):
        run(bumpy, regions=[[3]], region_strengths=["0.5"])


@pytest.mark.parametrize("regions", [[[0, 1, 2], [10, 11]], "labels"])
def test_all_zero_strengths_warn_naming_the_argument_not_a_deleted_file(bumpy, regions):
    """Before: "regions /tmp/tmpXXXX/regions.txt: every region's strength is 0: ...", naming the
    temporary file the arrays went through, deleted by the time the warning is read (regions that
    hold no region were already named as the argument)."""
    v, f = bumpy
    if regions == "labels":
        regions = np.full(len(f), -1)
        regions[[0, 1, 2]], regions[[10, 11]] = 0, 1
    r = shellcontract.contract(v, f, frames=1, regions=regions, region_strengths=[0, 0.0])
    assert r.summary["warnings"] == [
        "regions: every region's strength is 0: the local contraction has no effect"]
    assert r.summary["options"]["regions"] == "<2 regions given as arrays>"
