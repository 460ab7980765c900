"""Constraint III of a hysteretic VS over a range of amplitudes, not one (report Section 10.4, first item).

For LR and FP the design closes ``w -> z_vs`` with the describing function
(DF) of the isolator at one amplitude ``A`` (:mod:`..linearize`):
``Z(j w) = -w**2/(N(A, w) - m w**2)``.  This module certifies the passivity
margin of the controlled table for *every* ``A`` in ``[A_min, A_max]``:

1. At one frequency ``H_vw = a + b Z`` (affine in ``Z``: the table and the
   controller do not depend on the VS), so ``H_vw = a + beta/(N - p)`` is a
   Moebius function of the complex stiffness ``N``
   (:mod:`.box_margin`).
2. The amplitude range is cut into cells at log-spaced nodes; the DF (or,
   for ``vs_model="equivalent-viscous"``, ``k_eff + j w c_eq``) is
   computed at the nodes, and over a cell ``N(A, w)`` is enclosed in a
   rectangle: the box of the two end values, widened by a bound on the
   chord's deviation (``kappa/8`` times the largest second divided
   difference in ``log A`` of the neighbouring nodes, ``kappa`` =
   :data:`ENCLOSURE_SAFETY`).
3. The worst margin over each rectangle is exact, in closed form
   (:func:`.box_margin.worst_margin_deg`), at every frequency of a dense grid.
4. A cell that fails while one of its ends passes is split at its geometric
   middle (a new DF node), at most :data:`SPLIT_ROUNDS` times, so the
   certified sub-range ends close to where the margin really crosses.

What this proves, and what it does not: given the enclosure of step 2 (an
estimate from the DF's smoothness, checked by a test against a dense
amplitude grid; it is not a proof), the first-harmonic (DF) model of the
controlled table has a margin of at least ``delta`` at every amplitude of the
certified range and at every frequency of the grid.  Frequencies between grid
points are not covered (the grid is as dense as constraint III's own), and
the DF is an approximation of the nonlinear loop: no statement is made about
the time-domain passivity of the nonlinear system.

The sector view (:class:`SectorBound`) states the model's bounds, which hold
for any motion: the isolator's incremental stiffness lies in
``[k_post, k_initial]`` and its hysteretic force is bounded by ``F_h``.  From
the bound alone, the DF of the hysteretic part at any amplitude ``A' >= A``
lies in the half-disc ``|N_h| <= 4 F_h/(pi A)``, ``Im N_h >= 0`` (the first
Fourier coefficient of a signal bounded by ``F_h`` is at most ``4 F_h/pi``;
``Im N_h >= 0`` says the loop dissipates, which a test checks on the computed
DFs rather than proves).  :attr:`SectorBound.envelope_from_in` is the smallest
amplitude from which that envelope (as its bounding rectangle) certifies III:
a proof for the DF model at all larger amplitudes that needs no DF at all.
"""

from __future__ import annotations

import dataclasses
import time
from dataclasses import dataclass

import numpy as np

from ...errors import ConfigError
from ...plant import TableParameters
from ...units import TWO_PI
from ..constraints import DesignCriteria
from ..controller import ControllerDesign
from ..linearize import GRID_HZ, equivalent_linearization, harmonic_cycle, interpolate_stiffness
from .amplitude_results import (
    ENVELOPE_MAX_IN,
    AmplitudeCertificate,
    CellMargin,
    ModelMargin,
    SectorBound,
    summary,
)
from .box_margin import worst_margin_deg
from .exchange import log_points
from .models import TABLE_MODELS, RationalTarget, robust_set

#: Amplitude nodes per decade of the first pass.
NODES_PER_DECADE = 8

#: Frequency points per decade (constraint III's own grid density, design/passivity.py).
POINTS_PER_DECADE = 400

#: Safety factor on the chord-deviation estimate of the DF between nodes.
ENCLOSURE_SAFETY = 4.0

#: Rounds of splitting failing cells.
SPLIT_ROUNDS = 3

#: VS types whose describing function this module knows (their sector is stated from their parameters).
HYSTERETIC_KINDS = ("LR", "FP")

#: VS models the certificate can use (see :func:`node_stiffness`).
VS_MODELS = ("describing-function", "equivalent-viscous")


def check_amplitude_range(range_in) -> tuple[float, float]:
    """``(A_min, A_max)`` [in] with ``0 < A_min < A_max < inf``, else a ConfigError naming ``amplitude_range``."""
    try:
        lo, hi = (float(x) for x in range_in)
    except (TypeError, ValueError):
        raise ConfigError("amplitude_range", "two amplitudes A_min < A_max in in", range_in) from None
    if not (np.isfinite(lo) and np.isfinite(hi) and 0 < lo < hi):
        raise ConfigError("amplitude_range", "two amplitudes 0 < A_min < A_max in in", (lo, hi))
    return lo, hi


def sector_of(vs) -> tuple[float, float, float, float]:
    """``(k_post, k_initial, F_h, c)`` [lbf/in, lbf/in, lbf, lbf*s/in] of an LR or FP VS (module docstring)."""
    p = vs.to_dict()
    if vs.kind == "LR":  # F = alpha k_i x + c v + q_d h, |h| <= 1, dh/dx in [0, 1/u_y]
        return float(p["k_s"]), float(p["k_i"]), float(p["q_d"]), float(p["c"])
    # FP: F = k_s x + mu(v) W h, mu <= mu_max, dh/dx in [0, 1/u_y]
    return float(p["k_s"]), float(p["k_s"] + p["k_i"]), float(p["q_d"]), 0.0


def describing_table(vs, amplitude_in: float) -> np.ndarray:
    """The DF ``N(A, 2 pi f)`` [lbf/in] on :data:`..linearize.GRID_HZ`, as the design's linearization has it.

    For LR one cycle suffices: ``dh/dt`` is proportional to ``v``, so the
    hysteresis is rate-independent and only the dashpot ``c v`` adds
    ``j w c`` (a test holds this equal to the cycle-by-cycle table).
    """
    if vs.kind == "LR":
        c = float(vs.to_dict()["c"])
        hysteretic = harmonic_cycle(vs, amplitude_in, 1.0).stiffness - 1j * TWO_PI * c
        return hysteretic + 1j * TWO_PI * c * GRID_HZ
    return np.array([harmonic_cycle(vs, amplitude_in, f).stiffness for f in GRID_HZ])


@dataclass(frozen=True)
class NodeStiffness:
    """The VS model's complex stiffness at one amplitude node.

    Attributes
    ----------
    amplitude_in : float
        The node [in].
    table : ndarray of complex or None
        The DF on :data:`..linearize.GRID_HZ` [lbf/in] (``describing-function``).
    k_eff, c_eq : float
        Effective stiffness [lbf/in] and equivalent viscous damping [lbf*s/in] (``equivalent-viscous``).
    """

    amplitude_in: float
    table: np.ndarray | None = None
    k_eff: float = 0.0
    c_eq: float = 0.0

    def at(self, f_hz: np.ndarray) -> np.ndarray:
        """``N`` [lbf/in] at ``f_hz`` [Hz]: the DF as the design interpolates it, or ``k_eff + j w c_eq``."""
        if self.table is not None:
            return interpolate_stiffness(GRID_HZ, self.table, f_hz)
        return self.k_eff + 1j * TWO_PI * np.asarray(f_hz, dtype=float) * self.c_eq


def node_stiffness(vs, amplitude_in: float, vs_model: str) -> NodeStiffness:
    """:class:`NodeStiffness` of ``vs`` at ``amplitude_in`` [in] for ``vs_model`` (one of :data:`VS_MODELS`)."""
    if vs_model == "describing-function":
        return NodeStiffness(float(amplitude_in), table=describing_table(vs, amplitude_in))
    eq = equivalent_linearization(vs, amplitude_in, "equivalent-viscous")
    return NodeStiffness(float(amplitude_in), k_eff=eq.k_eff, c_eq=eq.c_eq)


@dataclass(frozen=True)
class _Loop:
    """``H_vw = a + b Z`` of one table model on the frequency grid (internal)."""

    name: str
    f_hz: np.ndarray
    a: np.ndarray
    beta: np.ndarray
    pole: np.ndarray

    def margins(self, x0, x1, y0, y1) -> np.ndarray:
        return worst_margin_deg(self.a, self.beta, self.pole, x0, x1, y0, y1)


def _loops(design: ControllerDesign, params: TableParameters, vs, band_hz, per_decade, models) -> list[_Loop]:
    f = log_points(band_hz, per_decade)
    w = TWO_PI * f
    out = []
    for model in robust_set(params, {"vs": RationalTarget(vs.linear_part().H_zw)}, models):
        r = model.responses(f)
        s = r.s_controller
        a = r.P_vw + r.P_vu * design.H_uw(s)
        b = r.P_vu * design.H_uz(s)
        out.append(_Loop(model.table_kind, f, a, -(w**2) * b, float(vs.m_vs) * w**2))
    return out


def _enclosures(nodes: np.ndarray, N: np.ndarray) -> tuple[np.ndarray, ...]:
    """Per cell and frequency the rectangle ``(x0, x1, y0, y1)`` [lbf/in] enclosing ``N(A, f)`` (module docstring).

    ``N`` is ``(node, frequency)``: the stiffness at the nodes ``nodes`` [in].
    """
    u = np.log(nodes)
    h = np.diff(u)
    slope = np.diff(N, axis=0) / h[:, None]
    curv = np.zeros_like(N, dtype=float)  # |N''| estimate at interior nodes
    if len(nodes) > 2:
        curv[1:-1] = np.abs(2.0 * np.diff(slope, axis=0) / (h[:-1] + h[1:])[:, None])
        curv[0], curv[-1] = curv[1], curv[-2]
    dev = ENCLOSURE_SAFETY * np.maximum(curv[:-1], curv[1:]) * h[:, None] ** 2 / 8.0
    lo, hi = N[:-1], N[1:]
    return (
        np.minimum(lo.real, hi.real) - dev,
        np.maximum(lo.real, hi.real) + dev,
        np.minimum(lo.imag, hi.imag) - dev,
        np.maximum(lo.imag, hi.imag) + dev,
    )


def _initial_nodes(lo: float, hi: float, per_decade: int) -> list[float]:
    """``lo``, ``hi`` and the decade-aligned points ``10**(k/per_decade)`` between them [in]."""
    k = np.arange(np.ceil(per_decade * np.log10(lo)), np.floor(per_decade * np.log10(hi)) + 1)
    inner = [float(v) for v in 10.0 ** (k / per_decade) if lo * (1 + 1e-9) < v < hi * (1 - 1e-9)]
    return [lo, *inner, hi]


def _cell_margins(loops: list[_Loop], nodes, stiffness) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """Model -> worst margin [deg] per (cell, frequency) and per (node, frequency) (no enclosure)."""
    out = {}
    for loop in loops:
        pts = np.array([n.at(loop.f_hz) for n in stiffness])  # (node, f)
        m = loop.margins(*_enclosures(np.asarray(nodes), pts))
        point = loop.margins(pts.real, pts.real, pts.imag, pts.imag)
        out[loop.name] = (m, point)
    return out


def _refined(loops: list[_Loop], vs, vs_model: str, nodes: list[float], delta: float):
    """Nodes [in] and cell margins after splitting the verdict model's failing cells with a passing end."""
    tables = [node_stiffness(vs, a, vs_model) for a in nodes]
    verdict = loops[0].name
    for rnd in range(SPLIT_ROUNDS + 1):
        res = _cell_margins(loops, nodes, tables)
        cell_min = res[verdict][0].min(axis=1)
        point = res[verdict][1].min(axis=1)
        split = [
            i
            for i in range(len(nodes) - 1)
            if cell_min[i] < delta and (point[i] >= delta or point[i + 1] >= delta)
        ]
        if not split or rnd == SPLIT_ROUNDS:
            break
        for i in reversed(split):
            mid = float(np.sqrt(nodes[i] * nodes[i + 1]))
            nodes.insert(i + 1, mid)
            tables.insert(i + 1, node_stiffness(vs, mid, vs_model))
    return nodes, res


def _model_margin(loop: _Loop, margins: tuple[np.ndarray, np.ndarray], nodes: list[float], delta: float):
    """The :class:`ModelMargin` of one table model from its (cell, frequency) and (node, frequency) margins."""
    cell, point = margins
    i, j = (int(v) for v in np.unravel_index(int(np.argmin(cell)), cell.shape))
    k, n = (int(v) for v in np.unravel_index(int(np.argmin(point)), point.shape))
    return ModelMargin(
        loop.name,
        float(cell[i, j]),
        (nodes[i], nodes[i + 1]),
        float(loop.f_hz[j]),
        bool(cell[i, j] >= delta),
        float(point[k, n]),
        float(nodes[k]),
        float(loop.f_hz[n]),
    )


def _largest_run(cells: list[CellMargin]) -> tuple[float, float] | None:
    best, start = None, None
    for i, c in enumerate([*cells, None]):
        if c is not None and c.certified:
            start = i if start is None else start
            continue
        if start is not None:
            run = (cells[start].amplitude_in[0], cells[i - 1].amplitude_in[1])
            if best is None or np.log(run[1] / run[0]) > np.log(best[1] / best[0]):
                best = run
            start = None
    return best


def _envelope(loop: _Loop, vs, delta: float) -> tuple[float | None, float]:
    """Smallest amplitude from which the sector's half-disc DF envelope certifies ``delta`` (module docstring)."""
    k_post, _, force, c = sector_of(vs)
    w = TWO_PI * loop.f_hz
    last = -90.0
    for amp in 10.0 ** np.arange(-2.0, np.log10(ENVELOPE_MAX_IN) + 1e-9, 0.25):
        R = 4.0 * force / (np.pi * amp)
        last = float(np.min(loop.margins(k_post - R, k_post + R, w * c, w * c + R)))
        if last >= delta:
            return float(amp), last
    return None, last


def amplitude_certificate(
    design: ControllerDesign,
    params: TableParameters,
    vs,
    amplitude_range_in: tuple[float, float],
    *,
    margin_deg: float | None = None,
    criteria: DesignCriteria | None = None,
    table_models: tuple[str, ...] = ("first-order", "sampled"),
    vs_model: str = "describing-function",
    nodes_per_decade: int = NODES_PER_DECADE,
    points_per_decade: int = POINTS_PER_DECADE,
) -> AmplitudeCertificate:
    """Certify constraint III of a standardized design for an LR/FP VS over an amplitude range.

    Parameters
    ----------
    design : ControllerDesign
        A standardized-form design (filter or optimized).
    params : TableParameters
        The physical table (its first-order and sampled-data models).
    vs : DefinedVS
        The LR or FP virtual system (not its linearization).
    amplitude_range_in : (float, float)
        ``(A_min, A_max)`` [in], ``0 < A_min < A_max``.
    margin_deg : float, optional
        Required margin ``delta`` [deg]; default the optimized design's ``--margin``, else 0.
    criteria : DesignCriteria, optional
        Its ``passivity_low_hz`` starts the band; the band ends at the Nyquist frequency.
    table_models : tuple of str
        Table models evaluated; the first is the verdict model.
    vs_model : str
        ``describing-function`` (the DF as the constraints use it) or
        ``equivalent-viscous`` (``s**2/(m s**2 + c_eq(A) s + k_eff(A))``, the rational model
        of the optimized design's grid-free certificate).
    nodes_per_decade, points_per_decade : int
        Initial amplitude nodes and frequency points per decade.

    Returns
    -------
    AmplitudeCertificate

    Raises
    ------
    ConfigError
        A bad range, a VS that is not LR/FP, a design that is not standardized, an analog table.
    """
    start = time.perf_counter()
    lo, hi = check_amplitude_range(amplitude_range_in)
    if getattr(vs, "kind", None) not in HYSTERETIC_KINDS:
        raise ConfigError("vs", "an LR or FP VS for an amplitude certificate", getattr(vs, "kind", vs))
    if design.form != "standardized":
        raise ConfigError("form", "the standardized form for an amplitude certificate", design.form)
    if not params.loop_time > 0:
        raise ConfigError("table", "a sampled table (loop_time > 0) for an amplitude certificate")
    if vs_model not in VS_MODELS:
        raise ConfigError("vs_model", " or ".join(VS_MODELS), vs_model)
    if not table_models or any(m not in TABLE_MODELS for m in table_models):
        raise ConfigError("table_models", "some of " + ", ".join(TABLE_MODELS), table_models)
    for key, value in (("nodes_per_decade", nodes_per_decade), ("points_per_decade", points_per_decade)):
        if isinstance(value, bool) or not isinstance(value, int) or value < 1:
            raise ConfigError(key, "a positive whole number", value)
    c = criteria or DesignCriteria()
    delta = float(
        margin_deg if margin_deg is not None else (design.optimization or {}).get("margin_deg", 0.0)
    )
    band = (c.passivity_low_hz, 0.5 / params.loop_time)
    loops = _loops(design, params, vs, band, points_per_decade, table_models)
    nodes, res = _refined(loops, vs, vs_model, _initial_nodes(lo, hi, nodes_per_decade), delta)
    verdict = loops[0].name
    f = loops[0].f_hz
    stable = bool(design.constraints[0].stable) if design.constraints else True
    cells = []
    for i in range(len(nodes) - 1):
        j = int(np.argmin(res[verdict][0][i]))
        worst_cell = float(res[verdict][0][i, j])
        cells.append(
            CellMargin(
                (nodes[i], nodes[i + 1]), worst_cell, float(f[j]), bool(stable and worst_cell >= delta)
            )
        )
    models = [_model_margin(loop, res[loop.name], nodes, delta) for loop in loops]
    worst = models[0]
    k_post, k_init, force, damping = sector_of(vs)
    env_from, env_margin = _envelope(loops[0], vs, delta)
    run = _largest_run(cells)
    return AmplitudeCertificate(
        range_in=(lo, hi),
        certified=bool(run == (lo, hi)),
        certified_range_in=run,
        required_margin_deg=delta,
        margin_deg=worst.margin_deg,
        binding_amplitude_in=worst.amplitude_in,
        binding_hz=worst.worst_hz,
        verdict_model=verdict,
        vs_model=vs_model,
        models=tuple(models),
        cells=tuple(cells),
        sector=SectorBound(k_post, k_init, force, damping, env_from, env_margin),
        stable=stable,
        band_hz=(float(band[0]), float(band[1])),
        points_per_decade=int(points_per_decade),
        nodes=len(nodes),
        wall_time_s=float(time.perf_counter() - start),
    )


def with_amplitude_certificate(design: ControllerDesign, cert: AmplitudeCertificate) -> ControllerDesign:
    """``design`` carrying ``cert`` (``passivity_amplitude_certificate`` in its JSON and design file);
    a certificate that fails adds a warning."""
    doc = cert.to_dict()
    notes = design.warnings if cert.certified else (*design.warnings, summary(doc))
    return dataclasses.replace(design, amplitude_certificate=doc, warnings=tuple(notes))
