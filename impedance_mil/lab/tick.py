"""One loop tick, written once: sense -> safety -> controller -> hydraulic -> advance.

:func:`sequence` writes the loop of a MIL program once, tick by tick as the
RMC75E runs it (Section 7.3.4), in terms of named *stages*: ``read``
(sense, then safety), ``record_vs_state``, ``track_step`` or ``mil_step``
(controller), ``command`` (hydraulic loop), ``truth``, ``record`` and
``advance``.  It is rendered three times, with three namespaces of stages of the same
names:

* :data:`run_loop` = ``numba.njit(sequence(lab.kernels))``: the compiled
  stages on the virtual plant's arrays (a
  :class:`~impedance_mil.lab.structures.VirtualPlant`, a
  :class:`~impedance_mil.lab.structures.LoopControl`, the VS tick and the
  :class:`~impedance_mil.lab.structures.Records`), inlined at numba-IR level
  into one loop -- the fast path of :func:`impedance_mil.lab.loop.simulate`;
* :data:`run_lti_loop` = ``numba.njit(sequence(lab.lti_kernels))``: the same
  loop on an LTI table (:class:`~impedance_mil.lab.structures.LTIPlant`);
* :data:`run_ticks` = ``sequence(lab.interface_stages)``: the same loop in
  Python against any :class:`~impedance_mil.lab.plant_interface.PlantInterface`
  and a :class:`~impedance_mil.implement.MILRuntime` -- the path of
  :func:`~impedance_mil.lab.loop.simulate_interface`, where a link to a real
  controller stands, and where a user-defined VS steps in Python.

So the order of the stages exists only here.  The stages themselves exist
once each for the virtual table: :class:`~impedance_mil.lab.plant_interface.VirtualTable`
implements the plant interface by calling the compiled stages of
:mod:`impedance_mil.lab.kernels`, and the records are one function
(:func:`~impedance_mil.lab.structures.record_loop`) on both paths; with
``VirtualTable`` the two renderings give the same numbers.

Why a closure over a stage *module*: numba inlines a call ``stages.read(...)``
at IR level when ``stages`` is a module it can see while compiling (a free
variable), as it inlines any ``inline="always"`` kernel, and the compiled loop
keeps the speed and the compile time of one hand-written loop.  (Typed
``@overload`` renderings of each stage compiled ~3x slower and ran slower;
separate, non-inlined stage functions ran 3x slower, passing the structures
by value at every call.)
"""

from __future__ import annotations

from numba import njit

from . import interface_stages, kernels, lti_kernels
from .inline_pipeline import LoopCompiler
from .structures import FEEDBACK_LC, MODE_OPEN, MODE_TRACK
from .trips import TripCause


def sequence(stages):
    """The loop over samples ``start ... stop - 1`` of ``control.a_g``, with the stages of the module ``stages``.

    Returns ``run(plant, control, vs_tick, log, start, stop) -> (loops
    completed, TripCause, value)``: every state lives in the structures, so a
    run in chunks (``0 ... k``, then ``k ... n``) is the same run as one call,
    bit for bit (:func:`impedance_mil.lab.chunks.run_in_chunks`).

    Loop k reads the plant (sense, safety: a trip ends the run before anything
    of loop k is recorded), records the VS state at the start of the loop,
    computes the command (open loop: ``control.command[k]``; tracking:
    ``z_vs = a_g``; MIL: the VS tick then the controller), sends it through the
    hydraulic loop, records the loop and lets the plant advance by one loop time.
    """

    def run(plant, control, vs_tick, log, start, stop):
        for k in range(start, stop):
            # 1. sense, 2. safety
            m, cause, value = stages.read(plant, k)
            if cause != TripCause.NONE:
                return k, cause, value
            w = m.w_lc if control.feedback == FEEDBACK_LC else m.w_fe
            a_g = control.a_g[k]
            stages.record_vs_state(log, k, control)
            # 3. controller (and VS)
            if control.mode == MODE_OPEN:
                u, z_vs, u_w = control.command[k], 0.0, 0.0
            elif control.mode == MODE_TRACK:
                u, u_w = stages.track_step(control, a_g, w)
                z_vs = a_g
            else:
                u, z_vs, u_w = stages.mil_step(control, vs_tick, a_g, w)
            # 4. hydraulic loop
            stages.command(plant, m, u)
            stages.record(log, k, m, stages.truth(plant), a_g, z_vs, u, u_w, w)
            # 5. advance
            stages.advance(plant)
        return stop, TripCause.NONE, 0.0

    return run


#: The loop in Python: ``run_ticks(plant: PlantInterface, control: LoopControl (controller: the
#: MILRuntime or None), None, log: Records, start, stop) -> (loops completed, TripCause, value)``.
run_ticks = sequence(interface_stages)

# ``pipeline_class=LoopCompiler``: numba's pipeline with a faster IR inliner, the same code
# (lab/inline_pipeline.py; the first run's compile of the loop: 109 s -> 55 s under load).
# ``_nrt=False``: the loop runs without numba's reference counting.  With it, every
# array view made per tick (a noise row, the specimen part of y, a work row) and
# many array arguments of the inlined kernels cost an atomic increment and
# decrement; perf showed those atomics at about 45 % of the loop's time.  The
# loop allocates nothing (its structures are made by the caller, who also keeps
# every array alive for the call), so it needs no NRT.
# ``nogil=True``: a run in chunks (lab/chunks.py) draws the next chunk's noise and writes the
# previous chunk's records to the run file while the loop runs.
_LOOP_JIT = dict(cache=True, error_model="numpy", _nrt=False, nogil=True, pipeline_class=LoopCompiler)
#: The loop compiled: ``run_loop(plant: VirtualPlant, control: LoopControl, vs_tick: VSTick,
#: log: Records, start, stop) -> (loops completed, TripCause, value)``; one compiled variant per
#: controller precision (float32, float64), for every VS and specimen.
run_loop = njit(**_LOOP_JIT)(sequence(kernels))

#: The loop compiled on an LTI table: ``run_lti_loop(plant: LTIPlant, control, vs_tick, log, start, stop)``,
#: the same sequence with the stages of :mod:`impedance_mil.lab.lti_kernels` (a loop of its
#: own: the physical table's loop above is untouched by it).
run_lti_loop = njit(**_LOOP_JIT)(sequence(lti_kernels))
