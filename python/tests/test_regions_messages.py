"""regions()'s refusals name the option as the caller spelt it, the value and the range, as the
CLI's do (review15 L8). Before: "region options: area fractions must satisfy 0 <= min <= max <= 1"
and "max concave fraction must be in [0, 1]", naming neither option nor value, and NaN for a
fraction said ">= 0" instead of its [0, 1]."""
import warnings

import pytest

import shellcontract


@pytest.mark.parametrize("options,said", [
    (dict(max_area_fraction=0, min_area_fraction=0.3), "max_area_fraction 0 is below min_area_fraction 0.3"),
    (dict(max_area_fraction=0.001), "max_area_fraction 0.001 is below min_area_fraction 0.002"),
    (dict(max_concave_fraction=1.5), r"max_concave_fraction: expected a number in \[0, 1\], got 1.5"),
    (dict(max_area_fraction=float("nan")), r"max_area_fraction: expected a number in \[0, 1\], got nan"),
    ({"min-area-fraction": 2.0}, r"min-area-fraction: expected a number in \[0, 1\], got 2.0"),
    (dict(min_cap_angle=200), r"min_cap_angle: expected a number of degrees in \[0, 180\], got 200"),
])
def test_a_bad_value_names_the_option_the_value_and_the_range(ico2, options, said):
    with pytest.raises(ValueError, match=said) as e:
        shellcontract.regions(*ico2, **options)
    assert "region options" not in str(e.value)
    assert "`" not in str(e.value)


def test_a_far_point_is_said_in_words_not_inf(ico2):
    """Before: "the 1st region_at point ... is inf from the surface"."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        shellcontract.regions(*ico2, region_at=[(1.7e308, 1.7e308, 1.7e308)])
    said = [str(w.message) for w in caught if "region_at" in str(w.message)]
    assert said and "inf" not in said[0] and "from the surface" in said[0], said
