"""Units in brackets survive in --help (issue 12: Rich markup ate [in], [lbf], [g] and [s])."""

from __future__ import annotations

import pytest


@pytest.mark.parametrize(
    "args, shown",
    [
        (("simulate", "--help"), "Scale to this PGA [g]"),
        (("table", "tf", "--help"), "z [in/s^2], x [in], v [in/s] or dp [psi]"),
        (("simulate", "--help"), "Filter cut-off [Hz]"),
    ],
)
def test_unit_brackets_are_printed(imil, args, shown):
    r = imil(*args)
    assert r.returncode == 0
    assert shown in " ".join(r.stdout.split())  # help is wrapped: compare with single spaces
