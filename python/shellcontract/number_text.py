"""The tool's number grammar (docs/cli.md, "Numbers") for the numbers the Python layer reads as
text itself: the sweep's own options and regions()'s options given as a str (region_numbers). It is the one the
library reads every option with (src/core/decimal_text.hpp, parse_decimal and
parse_decimal_integer), which the package cannot include. Python's int() and float() take more:
blanks around the number, '_' between digits, the digits of other scripts, inf, nan, infinity;
so `sweep --workers " 3"` and `--job-timeout 1_000` ran where `run` refuses them. Imports nothing
of the compiled core."""

import math
import re

# An optional sign, digits with an optional point (at least one digit), an optional exponent:
# std::from_chars's general format plus a leading '+', ASCII digits only.
_DECIMAL = re.compile(r"[+-]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][+-]?[0-9]+)?")
_INTEGER = re.compile(r"[+-]?[0-9]+")


def decimal(text):
    """The float of `text` when it is exactly one decimal number within a double's range, else
    None. As parse_decimal (std::from_chars): too large a number is none, and so is one too small
    for any double ("1e-400", which float() reads as 0); a subnormal one ("1e-320") is one."""
    if not isinstance(text, str) or not _DECIMAL.fullmatch(text):
        return None
    value = float(text)
    digits = text.lower().split("e")[0]
    if not math.isfinite(value) or (value == 0.0 and any(c in "123456789" for c in digits)):
        return None
    return value


def integer(text):
    """The int of `text` when it is exactly one decimal integer (an optional sign and digits:
    "+3" and "010" are, "3.0", " 3" and "1_000" are not), else None."""
    if not isinstance(text, str) or not _INTEGER.fullmatch(text):
        return None
    return int(text)


# regions()'s options whose values are not numbers.
_REGION_TEXT_OPTIONS = ("method", "region_at", "region-at")


def region_numbers(options):
    """regions()'s keyword options with each number given as a str read as contract() reads one
    (the CLI's text, this grammar; ValueError naming the option otherwise); other values as they
    are, for the core's checks of their types and ranges."""
    out = {}
    for name, value in options.items():
        if isinstance(value, str) and name not in _REGION_TEXT_OPTIONS:
            whole = name in ("min_faces", "min-faces")
            number = integer(value) if whole else decimal(value)
            if number is None:
                raise ValueError("regions() option {}: {!r} is not {}".format(
                    name, value, "an integer" if whole else "a number"))
            value = number
        out[name] = value
    return out
