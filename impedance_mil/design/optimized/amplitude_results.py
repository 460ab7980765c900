"""Named results of the amplitude certificate (:mod:`.amplitudes`): cells, per-model margins, sector, verdict."""

from __future__ import annotations

from dataclasses import dataclass

#: Largest amplitude [in] at which the sector envelope is tried.
ENVELOPE_MAX_IN = 1000.0

#: The method, as stated in the certificate.
METHOD = (
    "VS stiffness N(A, f) (DF, or k_eff + j w c_eq) at log-spaced amplitude nodes; per cell a rectangle of "
    "N(A, f) (end values widened by the "
    "chord-deviation estimate); exact worst margin of the Moebius image a + beta/(N - m w^2) over each "
    "rectangle (box_margin.py) on a dense frequency grid; failing cells split"
)


@dataclass(frozen=True)
class CellMargin:
    """One amplitude cell.

    Attributes
    ----------
    amplitude_in : (float, float)
        The cell [in].
    margin_deg : float
        Worst margin [deg] over the cell's enclosure and the frequency grid (verdict model).
    worst_hz : float
        Where [Hz].
    certified : bool
        ``margin_deg >= delta``.
    """

    amplitude_in: tuple[float, float]
    margin_deg: float
    worst_hz: float
    certified: bool

    def to_dict(self) -> dict:
        return {
            "amplitude_in": [float(x) for x in self.amplitude_in],
            "margin_deg": float(self.margin_deg),
            "worst_hz": float(self.worst_hz),
            "certified": bool(self.certified),
        }


@dataclass(frozen=True)
class ModelMargin:
    """Worst margin of one table model over the whole range.

    Attributes
    ----------
    model : str
        ``"first-order"`` or ``"sampled"``.
    margin_deg : float
        Worst margin [deg] over every cell's enclosure and the frequency grid.
    amplitude_in : (float, float)
        The cell where it is [in].
    worst_hz : float
        The frequency [Hz].
    certified : bool
        ``margin_deg >= delta`` on this model.
    node_margin_deg : float
        Worst margin [deg] at the nodes themselves (the DF computed there, no enclosure):
        the true worst margin over the range lies between ``margin_deg`` and this.
    node_amplitude_in, node_hz : float
        Where [in], [Hz].
    """

    model: str
    margin_deg: float
    amplitude_in: tuple[float, float]
    worst_hz: float
    certified: bool
    node_margin_deg: float
    node_amplitude_in: float
    node_hz: float

    def to_dict(self) -> dict:
        return {
            "model": self.model,
            "margin_deg": float(self.margin_deg),
            "amplitude_in": [float(x) for x in self.amplitude_in],
            "worst_hz": float(self.worst_hz),
            "certified": bool(self.certified),
            "node_margin_deg": float(self.node_margin_deg),
            "node_amplitude_in": float(self.node_amplitude_in),
            "node_hz": float(self.node_hz),
        }


@dataclass(frozen=True)
class SectorBound:
    """The isolator's sector, from its parameters, and the amplitudes its DF envelope certifies.

    Attributes
    ----------
    k_post, k_initial : float
        Incremental stiffness bounds [lbf/in] of the isolator force (LR: ``alpha k_i``
        and ``k_i``; FP: ``k_s`` and ``k_s + mu_max W/u_y``).
    force_bound_lbf : float
        Bound of the hysteretic force [lbf] (LR: ``q_d``; FP: ``mu_max W``).
    damping_lbf_s_per_in : float
        Linear viscous damping [lbf*s/in] outside the hysteresis (LR's ``c``; FP: 0).
    envelope_from_in : float or None
        Smallest amplitude [in] (tried at 4 per decade up to :data:`ENVELOPE_MAX_IN`) from
        which the half-disc envelope of the DF certifies the margin; None: nowhere.
    envelope_margin_deg : float
        The envelope's worst margin [deg] at ``envelope_from_in``, or at the largest amplitude tried.
    """

    k_post: float
    k_initial: float
    force_bound_lbf: float
    damping_lbf_s_per_in: float
    envelope_from_in: float | None
    envelope_margin_deg: float

    def to_dict(self) -> dict:
        return {
            "k_post_lbf_per_in": float(self.k_post),
            "k_initial_lbf_per_in": float(self.k_initial),
            "hysteretic_force_bound_lbf": float(self.force_bound_lbf),
            "damping_lbf_s_per_in": float(self.damping_lbf_s_per_in),
            "envelope_certified_from_in": None
            if self.envelope_from_in is None
            else float(self.envelope_from_in),
            "envelope_margin_deg": float(self.envelope_margin_deg),
            "envelope_tried_up_to_in": ENVELOPE_MAX_IN,
            "meaning": "incremental stiffness of the isolator force in [k_post, k_initial], hysteretic force "
            "bounded; for every amplitude >= envelope_certified_from_in the DF of any hysteresis within that "
            "bound (|N_h| <= 4 F_h/(pi A), Im N_h >= 0) gives the margin (null: no amplitude tried does)",
        }


@dataclass(frozen=True)
class AmplitudeCertificate:
    """Constraint III over an amplitude range (see the module docstring).

    Attributes
    ----------
    range_in : (float, float)
        Amplitude range asked for [in].
    certified : bool
        The whole range is certified on the verdict model (and the controlled table is stable).
    certified_range_in : (float, float) or None
        The largest certified contiguous sub-range [in] (the whole range when ``certified``).
    required_margin_deg : float
        ``delta`` [deg].
    margin_deg : float
        Worst margin [deg] over the range on the verdict model.
    binding_amplitude_in : (float, float)
        The cell [in] where it is.
    binding_hz : float
        The frequency [Hz] where it is.
    verdict_model : str
        Table model of the verdict (``"first-order"``: the design model of constraint III).
    vs_model : str
        ``describing-function`` or ``equivalent-viscous``.
    models : tuple of ModelMargin
        Every table model evaluated.
    cells : tuple of CellMargin
        The cells (verdict model).
    sector : SectorBound
    stable : bool
        The controlled table is stable (amplitude-independent: the VS enters only the feedforward path).
    band_hz : (float, float)
        Frequency band [Hz] and ``points_per_decade`` of the grid.
    points_per_decade : int
    nodes : int
        DF nodes computed.
    wall_time_s : float
    """

    range_in: tuple[float, float]
    certified: bool
    certified_range_in: tuple[float, float] | None
    required_margin_deg: float
    margin_deg: float
    binding_amplitude_in: tuple[float, float]
    binding_hz: float
    verdict_model: str
    vs_model: str
    models: tuple[ModelMargin, ...]
    cells: tuple[CellMargin, ...]
    sector: SectorBound
    stable: bool
    band_hz: tuple[float, float]
    points_per_decade: int
    nodes: int
    wall_time_s: float

    def to_dict(self) -> dict:
        return {
            "range_in": [float(x) for x in self.range_in],
            "certified": bool(self.certified),
            "certified_range_in": None
            if self.certified_range_in is None
            else [float(x) for x in self.certified_range_in],
            "required_margin_deg": float(self.required_margin_deg),
            "margin_deg": float(self.margin_deg),
            "binding_amplitude_in": [float(x) for x in self.binding_amplitude_in],
            "binding_hz": float(self.binding_hz),
            "verdict_model": self.verdict_model,
            "vs_model": self.vs_model,
            "stable": bool(self.stable),
            "models": [m.to_dict() for m in self.models],
            "cells": [c.to_dict() for c in self.cells],
            "sector": self.sector.to_dict(),
            "band_hz": [float(x) for x in self.band_hz],
            "points_per_decade": int(self.points_per_decade),
            "nodes": int(self.nodes),
            "wall_time_s": float(self.wall_time_s),
            "method": METHOD,
            "proven": "given the enclosure of N(A, f) between nodes, the describing-function model has "
            "passivity margin >= required_margin_deg at every amplitude of certified_range_in and every "
            "frequency of the grid",
            "not_proven": "the enclosure between nodes is an estimate from the DF's smoothness (checked "
            "against a dense amplitude grid by the tests); frequencies between grid points; passivity of the "
            "nonlinear loop itself (the DF is a first-harmonic approximation)",
        }


def summary(cert: dict) -> str:
    """One line for the human output from a certificate's ``to_dict()``."""
    lo, hi = cert["range_in"]
    where = (
        f"worst margin {cert['margin_deg']:.4g} deg at {cert['binding_hz']:.4g} Hz, "
        f"amplitudes {cert['binding_amplitude_in'][0]:.3g}-{cert['binding_amplitude_in'][1]:.3g} in"
    )
    if cert["certified"]:
        return f"III certified over amplitudes {lo:g}-{hi:g} in ({cert['verdict_model']} model; {where})"
    run = cert["certified_range_in"]
    part = f"certified only over {run[0]:.3g}-{run[1]:.3g} in" if run else "certified over no sub-range"
    return (
        f"III not certified over amplitudes {lo:g}-{hi:g} in: {part} ({cert['verdict_model']} model; {where})"
    )
