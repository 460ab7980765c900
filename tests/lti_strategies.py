"""Hypothesis strategies shared by the LTI tests: stable roots and proper transfer functions."""

import numpy as np
from hypothesis import strategies as st


def root_list(draw, k: int) -> np.ndarray:
    """``k`` stable roots with magnitudes in [1, 1e3] rad/s: real, or conjugate pairs of damping 0.02-0.9."""
    out: list[complex] = []
    while len(out) < k:
        w = 10 ** draw(st.floats(0.0, 3.0))
        if k - len(out) >= 2 and draw(st.booleans()):
            z = draw(st.floats(0.02, 0.9))
            p = complex(-z * w, w * np.sqrt(1 - z * z))
            out += [p, p.conjugate()]
        else:
            out.append(complex(-w))
    return np.array(out)
