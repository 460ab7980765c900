"""Compare computed coefficients with numbers printed in the report.

A number printed with n significant digits, e.g. "4.32e-12", is matched to
half a unit in its last printed digit (here +-0.005e-12): the tightest
tolerance the printed digits allow.
"""

import numpy as np


def half_unit(text: str) -> float:
    """Half a unit in the last printed digit of a number written like '4.32e-12'."""
    mantissa, _, exponent = text.lower().partition("e")
    decimals = len(mantissa.partition(".")[2])
    return 0.5 * 10.0 ** (int(exponent or 0) - decimals)


def assert_printed(actual, printed: list[str], what: str) -> None:
    actual = np.asarray(actual, dtype=float)
    assert actual.size == len(printed), f"{what}: {actual.size} coefficients, report prints {len(printed)}"
    for k, (a, text) in enumerate(zip(actual, printed)):
        assert abs(a - float(text)) <= half_unit(text) * (1 + 1e-9), (
            f"{what}[{k}]: computed {a:.6g}, printed {text} (+-{half_unit(text):.2g})"
        )
