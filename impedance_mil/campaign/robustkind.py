"""The campaign kind ``robust-mil``: the user's MIL test on the table of one point of the lab's uncertainty set.

Its run configuration is the user's :class:`~impedance_mil.lab.choices.Choices`
as plain data (:func:`choices_config`) and the point (``point``: key ->
value, internal units); the run is :func:`impedance_mil.lab.robust.sampled_test`
of the test those choices make, with the nominal design, and its metrics are
those of the ``mil`` kind's runs.  ``imil simulate --robust N``
(:mod:`impedance_mil.campaign.robust`) makes such campaigns.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from ..lab.choices import Choices, mil_test
from ..lab.robust import sampled_test
from .labkinds import controlled_metrics

#: The campaign kind of a sampled run.
KIND = "robust-mil"

#: Choices that are paths (made absolute so that any worker finds them).
_PATH_CHOICES = ("table", "design")


def choices_config(choices: Choices) -> dict[str, Any]:
    """``choices`` as plain data for a run configuration (paths absolute)."""
    out = dataclasses.asdict(choices)
    for key in ("table", "design"):
        if out[key] is not None:
            out[key] = str(Path(out[key]).resolve())
    if out["lab"] not in (None, "report"):
        out["lab"] = str(Path(out["lab"]).resolve())
    out["table_overrides"] = dict(out["table_overrides"])
    out["vs_overrides"] = dict(out["vs_overrides"])
    out["keys"] = dict(out["keys"])
    return out


def config_choices(config: Mapping[str, Any]) -> Choices:
    """The :class:`Choices` of :func:`choices_config`'s data."""
    data = dict(config)
    for key in _PATH_CHOICES:
        if data.get(key) is not None:
            data[key] = Path(data[key])
    return Choices(**data)


def run_robust_mil(config: dict[str, Any], out_path: Path) -> dict[str, Any]:
    """Run function of the ``robust-mil`` kind: the user's MIL test on the table of ``config["point"]``.

    Returns the metrics of the ``mil`` kind's controlled runs (``trip_limit`` after a trip).
    """
    test = sampled_test(mil_test(config_choices(config["choices"])), config["point"])
    return controlled_metrics(test, test.run(), "", out_path)
