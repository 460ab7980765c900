"""Robust stability of a lab's test: its design over the lab's ``[uncertainty]`` set (issue 17, item 3).

:func:`test_robustness` answers, before a run, whether the controller of a
tracking or MIL test stays stable with the test's article for every table in
the lab's uncertainty set (:func:`impedance_mil.design.robust.robust_margins`);
:func:`lab_article` is the article of a lab file (``imil design --robust``);
:func:`sampled_test` is the same test on the table of one point of the set,
with the controller still the nominal one (``imil simulate --robust N``).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping

from ..design import virtual_model
from ..design.forms import VirtualModel
from ..design.robust import DEFAULT_LHS_SAMPLES, RobustMargins, robust_margins
from ..design.sensor_channels import force_channel
from ..errors import ConfigError
from ..plant import TableParameters
from ..plant.uncertainty import UncertaintySet
from ..report_config import report_config
from ..specimens.sensors import SensorSuite
from ..systems import TransferFunction
from .choices import Choices, choose_specimen, mounted_choice, with_lab_defaults
from .descriptions import SpecimenChoice, TrackingTest
from .labfile import LabSetup


def lab_article(setup: LabSetup) -> SpecimenChoice:
    """The article of a lab file's ``[specimen]`` (the report's vessel for ``--lab report``), on its mounting."""
    choices = with_lab_defaults(Choices(lab=str(setup.path)), setup)
    return mounted_choice(choose_specimen(choices, report_config(), {}, default_kind="none"), setup)


def article_impedance(specimen: SpecimenChoice) -> TransferFunction:
    """The article's impedance ``w/z`` [lbf per in/s**2] (zero for the bare table)."""
    if specimen.specimen is None:
        return TransferFunction.constant(0.0)
    return specimen.specimen.impedance()


def test_vs_model(test: TrackingTest) -> VirtualModel | None:
    """The VS model a test's design answers to: the run's (``open-fh``, as ``lab.experiments.mil_design``)."""
    return None if test.vs is None else virtual_model(test.vs, linearization="open-fh")


def lab_force_sensor(suite: SensorSuite | None, feedback: str) -> TransferFunction | None:
    """The fed-back force's channel model ``S_w`` of a lab's sensors (None: no filter or delay on it).

    :func:`~impedance_mil.design.sensor_channels.force_channel` of the
    channels ``suite`` (None: the Table 7.1 channels, which have neither) for
    ``feedback`` (``lc`` or ``fe``): only a lab that gives its force channels
    a ``bandwidth`` or a ``delay`` changes the coupled-stability check.
    """
    return None if suite is None else force_channel(suite, feedback)


def require_uncertainty(uncertainty: UncertaintySet | None, option: str) -> UncertaintySet:
    """The lab's set, or a ConfigError naming ``option`` when the lab has no ``[uncertainty]``."""
    if uncertainty is None:
        raise ConfigError(option, "a lab file (--lab FILE) with an [uncertainty] section")
    return uncertainty


def test_robustness(
    test: TrackingTest, *, samples: int = DEFAULT_LHS_SAMPLES, seed: int = 0
) -> RobustMargins | None:
    """The worst-case margins of ``test``'s design with its article over its lab's set (None: no set).

    Raises
    ------
    ConfigError
        The test's table is an LTI table (no parameters to vary).
    """
    if test.lab.uncertainty is None:
        return None
    if not isinstance(test.table, TableParameters):
        raise ConfigError("uncertainty", "a physical table (an LTI table has no parameters to vary)")
    return robust_margins(
        test.design,
        test.table,
        test_vs_model(test),
        test.lab.uncertainty,
        article_impedance(test.specimen),
        test.specimen.label,
        samples=samples,
        seed=seed,
        force_sensor=lab_force_sensor(test.lab.sensors, test.controller.feedback.channel),
    )


def sampled_test(test: TrackingTest, point: Mapping[str, float]) -> TrackingTest:
    """``test`` on the table of ``point`` of its lab's set, run with the nominal design (a real table's case).

    The controller is the one designed for the nominal table (``test.design``);
    the virtual table, and the output delay of the lab's loop, are those of the point.
    """
    uncertainty = require_uncertainty(test.lab.uncertainty, "uncertainty")
    if not isinstance(test.table, TableParameters):
        raise ConfigError("uncertainty", "a physical table (an LTI table has no parameters to vary)")
    table = uncertainty.apply(test.table, point)
    lab = dataclasses.replace(test.lab, output_delay=table.output_delay_loops)
    return dataclasses.replace(test, table=table, lab=lab, given_design=test.design)
