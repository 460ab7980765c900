"""The first run compiles some kernels in a side process while it compiles the loop (issue 16, goal 4).

A first ``imil simulate`` compiles the compiled loop (:data:`impedance_mil.lab.tick.run_loop`,
most of the first run), within it the loop's compressed-row plant step (a function of its own,
:data:`impedance_mil.lab.stepping.advance_csr_called`: about 4 s), and then, evaluating its
metrics, the kernels of :func:`impedance_mil.signals.response_spectrum` (``_coefficients``, a
4x4 matrix exponential by numpy's ``eye`` and ``@``, and ``_peak_responses``: 3-4 s).  Those
two do not depend on the rest, so :func:`kernels_compiled_aside` starts ``python -m
impedance_mil.lab.compile_aside`` at the start of the first run: it compiles them, the plant
step first, into numba's cache (the same ``NUMBA_CACHE_DIR``, inherited) on the other core
while this process compiles the virtual system, the table's physics and the loop.  numba looks
in its cache before it compiles a callee, so when the plant step is cached by the time the
loop's typing reaches it, the loop loads it (else it compiles it too, as before); when the
loop's compile ends this process waits for the side process, so that its first spectrum loads
the kernels from the cache instead of compiling them.  The work is moved to the other core,
not removed: with no free core it gains nothing.

The side process changes no result: it writes numba's cache of the same source, which numba
writes atomically (a temporary file, then a rename) and which this process would have written
itself.  When it fails, is not done within :data:`WAIT_S`, or imports another copy of the
package (which caches under that copy's own paths), nothing breaks: this process compiles
the kernels itself, as before.  A side process still running when the run ends is stopped.
"""

from __future__ import annotations

import os
import subprocess
import sys
from collections.abc import Iterator
from contextlib import contextmanager

import numpy as np
from numba import typeof
from numba.core import event

from ..plant import TableParameters
from ..plant.nonlinear import N_TABLE_STATES, NonlinearTable
from ..signals.spectrum import response_spectrum
from ..specimens import FluidVessel
from .plant_interface import specimen_arrays
from .stepping import advance_csr_called
from .structures import FilterArrays

#: The module whose compiled dispatchers are "the loop": the side process is waited for when a
#: top-level compile of one of them ends.
LOOP_MODULE = "impedance_mil.lab.tick"

#: At most this long [s] the run waits for the side process after the loop's compile.
WAIT_S = 120.0


def compile_spectrum_kernels() -> None:
    """Compile :func:`~impedance_mil.signals.response_spectrum`'s kernels for the argument types a run uses.

    ``imil simulate``'s metrics pass writable float64 accelerations (a read-only array would
    be another variant, which ``simulate`` does not compile).
    """
    response_spectrum(np.sin(np.linspace(0.0, 6.0, 64)), 0.01, [0.1, 1.0])


def csr_step_signature() -> tuple:
    """The argument types the loop passes :data:`~impedance_mil.lab.stepping.advance_csr_called`.

    The loop calls it (not inlined) on its compressed-row plant path, and numba compiles it
    while it types the loop unless the cache has it; the types are those of a
    :class:`~impedance_mil.lab.structures.VirtualPlant`'s fields.
    """
    table = NonlinearTable.from_linear(TableParameters.report_default())
    s = specimen_arrays(FluidVessel.report_default(), oscillator_bank=False)
    n = N_TABLE_STATES + s.B.size
    args = (
        *(table.parameter_array(), np.zeros(n)),
        *(s.A_val, s.A_col, s.A_ptr, s.B, s.C, s.D, s.C_lc, s.D_lc, s.lc_own),
        *(0.0, table.loop_time, 2, np.zeros((5, n)), FilterArrays.none()),
    )
    return tuple(typeof(a) for a in args)


def compile_csr_step() -> None:
    """Compile :data:`~impedance_mil.lab.stepping.advance_csr_called` for :func:`csr_step_signature` (not run)."""
    advance_csr_called.compile(csr_step_signature())


def usable_cpus() -> int:
    """CPUs this process may run on (its affinity where the platform tells it, else the machine's count)."""
    affinity = getattr(os, "sched_getaffinity", None)
    return len(affinity(0)) if affinity is not None else (os.cpu_count() or 1)


def start() -> subprocess.Popen | None:
    """Start the side process (this interpreter, this environment), or None when it cannot start.

    None as well with a single usable CPU: the side process would only compete with this one
    (and compile the plant step twice when it is late).
    """
    if usable_cpus() < 2:
        return None
    try:
        return subprocess.Popen(
            [sys.executable, "-m", __name__],
            stdin=subprocess.DEVNULL,
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
            env=dict(os.environ),
        )
    except OSError:
        return None


def finish(process: subprocess.Popen | None, timeout_s: float) -> bool:
    """Wait up to ``timeout_s`` [s] for the side process; stop it if it is not done.  True when it succeeded."""
    if process is None:
        return False
    try:
        return process.wait(timeout=timeout_s) == 0
    except subprocess.TimeoutExpired:
        process.kill()
        process.wait()
        return False


class WaitAfterLoop(event.Listener):
    """Waits for the side process when a top-level compile of the loop (:data:`LOOP_MODULE`) ends.

    Parameters
    ----------
    process : subprocess.Popen or None
        The side process (None: nothing to wait for).
    timeout_s : float
        At most this long [s] it waits.
    """

    def __init__(self, process: subprocess.Popen | None, timeout_s: float = WAIT_S) -> None:
        self._process = process
        self._timeout_s = timeout_s
        self._stack: list[bool] = []
        #: Whether the side process was waited for, and succeeded (None: not waited for yet).
        self.succeeded: bool | None = None

    def on_start(self, ev: event.Event) -> None:
        dispatcher = (ev.data or {}).get("dispatcher")
        module = getattr(getattr(dispatcher, "py_func", None), "__module__", None) or ""
        self._stack.append(not self._stack and module == LOOP_MODULE)

    def on_end(self, ev: event.Event) -> None:
        if self._stack.pop() and self.succeeded is None:
            self.succeeded = finish(self._process, self._timeout_s)


@contextmanager
def kernels_compiled_aside(timeout_s: float = WAIT_S) -> Iterator[WaitAfterLoop]:
    """Within the block (a first run), the plant step and the spectra's kernels compile in a side process (module docstring)."""
    process = start()
    listener = WaitAfterLoop(process, timeout_s)
    try:
        with event.install_listener("numba:compile", listener):
            yield listener
    finally:
        if process is not None and process.poll() is None:
            process.kill()
            process.wait()


if __name__ == "__main__":
    compile_csr_step()
    compile_spectrum_kernels()
