"""Why a run stopped: the trip causes, one enumeration from the kernel to the campaign claims.

:class:`TripCause` is shared by everything that knows about trips: the
compiled safety check (:func:`impedance_mil.lab.kernels.check_limits`
returns a member; numba compiles the members as integer constants), the
:class:`Trip` of a :class:`~impedance_mil.lab.results.RunResult`, the HDF5
run file (the cause's name and code), :class:`~impedance_mil.errors.LimitTripped`,
the command line's JSON (``trip.limit`` is the cause's name) and the campaign
claims (:mod:`impedance_mil.campaign.claims` reads the cause, never a
message).

The names are those run files have always carried (``"stroke"``,
``"velocity"``, ``"actuator_force"``, ``"valve_saturation"``, ``"nan"``,
``"divergence"``; since issue 18 also ``"valve_duty"``, ``"valve_current"`` and
``"command_oscillation"``; since issue 12 ``"acceleration"`` and ``"pressure"``; since issue 17
``"hf_oscillation"``, the growing high-frequency oscillation of
:mod:`impedance_mil.lab.oscillation`, whose value is the rms [in/s**2] of the
high-passed measured acceleration over the window that tripped; see
:class:`~impedance_mil.lab.setup.SafetyLimits`): :attr:`TripCause.label` is the member's name in lower
case, so a new cause is one line of the enumeration (its code and the unit of
the value it reports), plus the check that raises it.
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import IntEnum

from ..errors import LimitTripped

#: Column of a campaign summary row holding the cause's name (the ``limit`` of
#: :meth:`Trip.to_dict`, flattened by :func:`impedance_mil.lab.runfile.flat_summary`).
TRIP_LIMIT_KEY = "trip_limit"


class TripCause(IntEnum):
    """A safety limit (or a numerical failure) that stops a run; ``NONE`` while all is clear.

    Each member is ``code, unit``: the integer the compiled loop returns and the
    unit of the offending value it reports (internal units; empty when the
    value may be any state).
    """

    NONE = 0, ""
    STROKE = 1, "in"
    VELOCITY = 2, "in/s"
    ACTUATOR_FORCE = 3, "lbf"
    VALVE_SATURATION = 4, "V"
    NAN = 5, ""
    DIVERGENCE = 6, "in"
    VALVE_DUTY = 7, ""
    VALVE_CURRENT = 8, "mA"
    COMMAND_OSCILLATION = 9, "V/s"
    ACCELERATION = 10, "in/s**2"
    PRESSURE = 11, "psi"
    HF_OSCILLATION = 12, "in/s**2"

    unit: str

    def __new__(cls, code: int, unit: str) -> TripCause:
        member = int.__new__(cls, code)
        member._value_ = code
        member.unit = unit
        return member

    @property
    def label(self) -> str:
        """The name in run files, JSON and messages (``"stroke"``, ``"valve_saturation"`` ...)."""
        return self.name.lower()

    @classmethod
    def from_label(cls, label: str) -> TripCause:
        """The member named ``label`` (as :attr:`label` writes it).

        Raises
        ------
        ValueError
            ``label`` names no cause.
        """
        try:
            return cls[str(label).upper()]
        except KeyError:
            known = ", ".join(c.label for c in cls if c is not cls.NONE)
            raise ValueError(f"unknown trip cause {label!r} (known: {known})") from None


@dataclass(frozen=True)
class Trip:
    """A safety limit that stopped a run.

    Attributes
    ----------
    cause : TripCause
        What tripped.
    time_s : float
        Time of the trip [s]; records stop just before it.
    value : float
        The offending value, in :attr:`unit`.
    """

    cause: TripCause
    time_s: float
    value: float

    @property
    def limit(self) -> str:
        """The cause's name (``"stroke"`` ...), as files and JSON carry it."""
        return self.cause.label

    @property
    def unit(self) -> str:
        """Unit of :attr:`value` (``"in"``, ``"in/s"``, ``"lbf"``, ``"V"``; empty for NaN)."""
        return self.cause.unit

    @property
    def detail(self) -> str:
        return f"value {self.value:.6g}"

    def as_exception(self) -> LimitTripped:
        """The :class:`~impedance_mil.errors.LimitTripped` describing this trip."""
        return LimitTripped(self.cause, self.time_s, self.detail, value=self.value)

    def to_dict(self) -> dict:
        """``{"limit", "time_s", "value", "unit"}``: the ``trip`` entry of JSON summaries (internal units)."""
        return {"limit": self.limit, "time_s": self.time_s, "value": self.value, "unit": self.unit}
