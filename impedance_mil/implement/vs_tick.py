"""The VS slot of the MIL step: one compiled function per VS, passed to the kernels as a value.

A VS enters the compiled MIL step (:func:`impedance_mil.implement.runtime.mil_step_kernel`)
and the lab loop as its *tick*, for dtype ``T`` = float32 (single-precision
controller) or float64 (double)::

    z_vs = tick(params: T[::1], x: T[::1], a_g: T, w: T, dt: T, work: T[::1]) -> T

returns the VS output z_vs [in/s^2] computed from the state at the start of
the loop (``(w - F)/m_vs``), then advances ``x`` in place by one RK3 step
[s] with ``a_g`` [in/s^2] and ``w`` [lbf] held (report Figure 7.9).  The
kernels that call it know nothing of VS kinds.

:class:`VSTick` carries the compiled function to numba as a first-class
function of that one signature (numba's ``FunctionType``), so a caller is
compiled once per dtype for every VS and cached.  Measured on the
development VM, per call from Python: a ``VSTick`` argument costs ~20 us of
dispatch, a numba dispatcher inside a tuple ~0.5-1.4 ms (numba types it and
looks its address up in LLVM on every call, and warns each time), and a
dispatcher in a named tuple is typed per function (one compile per VS).

:func:`vs_tick_function` gives the tick of a defined VS (its kernel generated
from the type's definition, :mod:`impedance_mil.virtual.codegen`);
:func:`no_vs_tick` the placeholder of runs without a VS.
"""

from __future__ import annotations

import functools
import warnings
from typing import NamedTuple

import numpy as np
from numba import types
from numba.core.errors import NumbaExperimentalFeatureWarning
from numba.experimental.function_type import _get_wrapper_address

from ..errors import ConfigError
from ..virtual.codegen import compiled
from ..virtual.kernels import no_vs_tick32, no_vs_tick64
from ..virtual.system import DefinedVS

#: numba types of the tick's dtype, by numpy dtype name.
_SCALAR = {"float32": types.float32, "float64": types.float64}


class VSArrays(NamedTuple):
    """The VS slot's arrays, in the controller's dtype: ``params``, state ``x`` (in place), RK3 ``work``."""

    params: np.ndarray
    x: np.ndarray
    work: np.ndarray


def tick_signature(dtype) -> types.Signature:
    """``T(T[::1], T[::1], T, T, T, T[::1])`` for ``dtype`` (float32 or float64)."""
    name = np.dtype(dtype).name
    if name not in _SCALAR:
        raise ConfigError("dtype", "float32 or float64", name)
    t = _SCALAR[name]
    arr = types.Array(t, 1, "C")
    return t(arr, arr, t, t, t, arr)


class VSTick:
    """A compiled VS tick of :func:`tick_signature`, usable inside numba code as a value.

    numba types it as ``FunctionType(signature)`` (through ``_numba_type_``)
    and calls it through its C wrapper's address (``__wrapper_address__``,
    numba's wrapper-address protocol), resolved once here.  Calling it from
    Python runs the compiled function.

    Parameters
    ----------
    dispatcher : numba dispatcher
        An ``njit`` function compiled for ``signature``.
    signature : numba Signature
        :func:`tick_signature` of its dtype.
    """

    def __init__(self, dispatcher, signature: types.Signature):
        self.dispatcher = dispatcher
        self._signature = signature
        self._numba_type_ = types.FunctionType(signature)
        self._address = _get_wrapper_address(dispatcher, signature)

    def signature(self) -> types.Signature:
        return self._signature

    def __wrapper_address__(self) -> int:
        return self._address

    def __call__(self, params, x, a_g, w, dt, work):
        return self.dispatcher(params, x, a_g, w, dt, work)

    def __repr__(self) -> str:
        return f"VSTick({self.dispatcher.__name__}: {self._signature})"


@functools.cache
def _wrapped(dispatcher, dtype_name: str) -> VSTick:
    sig = tick_signature(dtype_name)
    with warnings.catch_warnings():
        # Taking the address of a function meant to be passed as a first-class function:
        # numba calls the feature experimental; the signature is fixed and tested.
        warnings.simplefilter("ignore", NumbaExperimentalFeatureWarning)
        return VSTick(dispatcher, sig)


def vs_tick_function(vs, dtype) -> VSTick:
    """The compiled tick of a VS of a defined type in ``dtype`` (float32 or float64).

    The kernel is generated from the type's definition and compiled once per
    definition and dtype (:func:`impedance_mil.virtual.codegen.compiled`).

    Raises
    ------
    ConfigError
        ``vs`` is not a :class:`~impedance_mil.virtual.system.DefinedVS` (a VS
        written as Python methods steps in Python, see
        :class:`~impedance_mil.implement.MILRuntime`).
    """
    if not isinstance(vs, DefinedVS):
        raise ConfigError("vs", "a virtual system of a defined type for a compiled tick", type(vs).__name__)
    name = np.dtype(dtype).name
    tick_signature(name)  # refuses other dtypes by name
    return _wrapped(compiled(vs.definition).tick(np.dtype(dtype)), name)


def no_vs_tick(dtype) -> VSTick:
    """A tick of the same signature for runs without a VS (open loop, tracking); returns 0."""
    name = np.dtype(dtype).name
    tick_signature(name)
    return _wrapped(no_vs_tick32 if name == "float32" else no_vs_tick64, name)
