"""The helpers of lab/scripts/cache_profile.py: reading a cachegrind output file, the per-face and
per-step difference of two runs, the grouping by name and the short names (no valgrind run)."""
import pathlib
import sys

import pytest

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1] / "scripts"))
import cache_profile  # noqa: E402

# A cachegrind file in the format valgrind 3.19 writes (with --branch-sim=yes): its events in an
# order other than the script's, a function split over two source files (header code inlined into
# it) and a line with fewer counts than events (cachegrind leaves trailing zeros out).
TASK = ("tbb::detail::d1::start_for<tbb::detail::d1::blocked_range<long>, "
        "shellcontract::pressure_forces(Eigen::Matrix<double, -1, 3, 1, -1, 3> const&)"
        "::{lambda(long)#1}>::execute()")
CACHEGRIND = f"""desc: I1 cache:         32768 B, 64 B, 8-way associative
cmd: ./sc run bear.off
events: Ir I1mr ILmr Dr D1mr DLmr Dw D1mw DLmw Bc Bcm Bi Bim
fl=/src/a.cpp
fn=shellcontract::f(int)
10 100 1 1 40 4 2 20 3 1 30 6 2 1
11 50 0 0 10 1
fl=/usr/include/eigen3/Eigen/src/Core/Block.h
fn=shellcontract::f(int)
7 5 0 0 1 0 0 1 1 1
fn={TASK}
3 7 0 0 2 2 2 0 0 0
summary: 162 1 1 53 7 4 21 4 2 30 6 2 1
"""


def test_load_sums_each_function_over_its_files_by_event_name(tmp_path):
    path = tmp_path / "cg.out"
    path.write_text(CACHEGRIND)
    counts = cache_profile.load(str(path))
    # EVENTS = Ir, D1mr, DLmr, D1mw, DLmw, Bcm, Bim: f's lines 100 + 50 + 5 Ir; D1mr 4 + 1 + 0;
    # DLmr 2 + 0 + 0 (the short line has none); D1mw 3 + 0 + 1; DLmw 1 + 0 + 1; Bcm 6; Bim 1.
    assert counts["shellcontract::f(int)"] == [155, 5, 2, 4, 2, 6, 1]
    task = [fn for fn in counts if fn.startswith("tbb::")]
    assert len(task) == 1 and counts[task[0]] == [7, 2, 2, 0, 0, 0, 0]
    assert len(counts) == 2


def test_per_face_step_is_the_difference_per_face_and_step():
    run = {"f": [600, 60, 6, 0, 0, 9, 0], "only_in_run": [30, 0, 0, 0, 0, 0, 0]}
    setup = {"f": [300, 30, 0, 0, 0, 12, 0], "only_in_setup": [90, 0, 0, 0, 0, 0, 0]}
    out = cache_profile.per_face_step(run, setup, faces=10, steps=3)
    assert out["f"] == pytest.approx([10.0, 1.0, 0.2, 0.0, 0.0, -0.1, 0.0], rel=1e-12)
    assert out["only_in_run"][0] == 1.0
    assert out["only_in_setup"][0] == -3.0  # setup work the run of N frames did not redo


def test_groups_by_the_first_pattern_that_matches():
    assert cache_profile.group_of("shellcontract::project_dihedral_hinge(...)") == \
        "solve: dihedral hinges"
    assert cache_profile.group_of("__ieee754_atan2_fma") == "solve: dihedral hinges"
    assert cache_profile.group_of(
        "shellcontract::detail::grid_pairs(...)::{lambda(unsigned long)#6}") == \
        "broad phase: cell loop and pair output"
    assert cache_profile.group_of("shellcontract::separating_axis_culls(...)") == "filter"
    assert cache_profile.group_of("malloc") == "other"


def test_short_names_drop_arguments_and_templates_and_name_tbb_tasks_by_their_body():
    assert cache_profile.short(
        "shellcontract::(anonymous namespace)::membrane_batches_avx2(double, "
        "shellcontract::MembraneBatch const*) [clone .isra.0]") == \
        "shellcontract::membrane_batches_avx2 [clone .isra.0]"
    assert cache_profile.short(
        "std::vector<int, std::allocator<int> >::_M_fill_assign(unsigned long, int const&)") == \
        "std::vector::_M_fill_assign"
    task = ("tbb::detail::d1::start_for<tbb::detail::d1::blocked_range<long>, "
            "shellcontract::pressure_forces(Eigen::Matrix<double, -1, 3, 1, -1, 3> const&)"
            "::{lambda(long)#1}>::execute()")
    assert cache_profile.short(task) == "TBB task of shellcontract::pressure_forces"


def test_ratio_leaves_out_counts_too_small_to_divide_by():
    assert cache_profile.ratio(3.0, 1.5) == "2.00x"
    assert cache_profile.ratio(5.94, 0.0) == "-"
    assert cache_profile.ratio(5.94, 0.001) == "-"
