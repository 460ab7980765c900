"""The one table mapping a campaign *kind* to its run function and parameters.

A run function has the signature ``run(config: dict, out_path: Path) -> dict``:
it receives the full run configuration (internal units), writes its data to
``out_path`` (an empty temporary file that becomes the file its kind names in
``output`` when the function returns), and returns a flat mapping of metric
names to numbers.  Raising :class:`~impedance_mil.errors.LimitTripped`
records the run as *aborted* (a legitimate outcome of a test); any other
exception records it as *failed* with its reason.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from types import MappingProxyType
from typing import Any

from ..errors import ConfigError
from .labkinds import (
    FRF_DEFAULTS,
    FRF_PARAMS,
    MIL_DEFAULTS,
    MIL_PARAMS,
    TRACKING_DEFAULTS,
    TRACKING_PARAMS,
    resolve_motion,
    run_frf_kind,
    run_mil_kind,
    run_tracking_kind,
)
from .modelkinds import (
    DESIGN_DEFAULTS,
    DESIGN_PARAMS,
    TABLE_POLES_DEFAULTS,
    TABLE_POLES_PARAMS,
    run_design,
    run_table_poles,
)
from .params import Param
from .robustkind import KIND as ROBUST_KIND
from .robustkind import run_robust_mil
from .selftest import SELFTEST_DEFAULTS, SELFTEST_PARAMS, run_selftest

#: Signature of a run function.
RunFunction = Callable[[dict[str, Any], Path], Mapping[str, Any]]


@dataclass(frozen=True)
class Kind:
    """A campaign kind: what one run does and which parameters it accepts.

    Parameters
    ----------
    name : str
        Name used in campaign files (``kind = "mil"``).
    run : callable
        ``run(config, out_path) -> dict of metrics``.
    params : mapping of str to Param
        The parameters a campaign may set or vary.
    defaults : mapping
        The base run configuration before the campaign's settings.
    description : str
        One line for listings.
    resolve : callable, optional
        ``resolve(config) -> config`` applied when the campaign is expanded,
        before the run is named: it writes into the configuration what the
        run will really use but the campaign does not say (e.g. which record
        stands for GM2), so that the run name changes when that does.
    output : str
        Name of the file a run writes in its folder: ``run.h5`` only for lab
        run files (``lab.results.load_run``, ``imil report``), another name
        for anything else.
    """

    name: str
    run: RunFunction
    params: Mapping[str, Param]
    defaults: Mapping[str, Any] = field(default_factory=dict)
    description: str = ""
    resolve: Callable[[dict[str, Any]], dict[str, Any]] | None = None
    output: str = "run.h5"


#: Every campaign kind, by name (read-only).
KINDS: Mapping[str, Kind] = MappingProxyType(
    {
        "selftest": Kind(
            "selftest",
            run_selftest,
            SELFTEST_PARAMS,
            SELFTEST_DEFAULTS,
            "modes of an SD isolator (engine and cluster check; no virtual lab)",
            output="selftest.h5",
        ),
        "table-poles": Kind(
            "table-poles",
            run_table_poles,
            TABLE_POLES_PARAMS,
            TABLE_POLES_DEFAULTS,
            "closed-loop poles of the table model (Section 4.4 tuning)",
            output="poles.h5",
        ),
        "design": Kind(
            "design",
            run_design,
            DESIGN_PARAMS,
            DESIGN_DEFAULTS,
            "MIL controller design and constraints I-III (Sections 6, 9.4)",
            output="design.json",
        ),
        "frf": Kind(
            "frf",
            run_frf_kind,
            FRF_PARAMS,
            FRF_DEFAULTS,
            "multisine identification of the virtual table (Section 4.5)",
        ),
        "tracking": Kind(
            "tracking",
            run_tracking_kind,
            TRACKING_PARAMS,
            TRACKING_DEFAULTS,
            "acceleration tracking on the virtual table (Section 8)",
            resolve_motion,
        ),
        "mil": Kind(
            "mil",
            run_mil_kind,
            MIL_PARAMS,
            MIL_DEFAULTS,
            "MIL with a virtual isolation system (Section 9)",
            resolve_motion,
        ),
        ROBUST_KIND: Kind(
            ROBUST_KIND,
            run_robust_mil,
            {},
            {},
            "the user's MIL test on one table of a lab's uncertainty set, nominal design "
            "(imil simulate --robust; no campaign-file parameters)",
        ),
    }
)


def get_kind(name: str) -> Kind:
    """Look up a campaign kind.

    Raises
    ------
    ConfigError
        The kind is unknown.
    """
    try:
        return KINDS[name]
    except KeyError:
        raise ConfigError("campaign.kind", "one of " + ", ".join(sorted(KINDS)), name) from None
