"""The loop's compiler pipeline (lab/inline_pipeline.py) makes the code numba's own pipeline makes.

Reference: numba's default pipeline on the same function.  The generated LLVM IR is compared
text for text, after the numbers numba appends to make names unique per compile (``v12``) are
masked.  The loop itself takes minutes to compile, so a small nest of ``inline="always"`` kernels
with branches and loops stands for it here; for the loop, benchmarks/bench_first_run.py and the
issue-16 note record the same check (identical LLVM IR and run files).
"""

import copy
import re

import numpy as np
from numba import njit
from numba.core import inline_closurecall, ir

from impedance_mil.lab.inline_pipeline import (
    FreshCalleeInliner,
    InlineSharingScope,
    LoopCompiler,
    fresh_callees_not_copied,
    scopes_shared_by_deepcopy,
)


@njit(inline="always")
def _clip(x, limit):
    if x > limit:
        return limit
    if x < -limit:
        return -limit
    return x


@njit(inline="always")
def _step(state, u, dt):
    acc = 0.0
    for i in range(state.shape[0]):
        acc += state[i] * (i + 1)
    state[0] += dt * _clip(u - acc, 5.0)
    return _clip(acc, 3.0)


def _loop(state, inputs, out, dt):
    for k in range(inputs.shape[0]):
        out[k] = _step(state, inputs[k], dt) + _step(state, -inputs[k], dt)
    return out.sum()


def _masked(llvm: str) -> str:
    """The IR with the per-compile name numbers masked (a mangled name carries the length of "v12"
    too, and so does the constant string that spells it)."""
    text = re.sub(r"(B\d+)?v\d+", "v#", llvm)
    text = re.sub(r"\[\d+ x i8\] c\"missing Environment", '[n x i8] c"missing Environment', text)
    # Block labels come from numba's process-wide label counter: numbered again by first appearance.
    labels: dict[str, str] = {}
    text = re.sub(r" +", " ", text)  # the "; preds" comments are aligned to the label's width
    return re.sub(r"\bB\d+\b", lambda m: labels.setdefault(m.group(), f"B#{len(labels)}"), text)


def test_the_loop_compiler_generates_the_same_llvm_ir_and_results_as_numbas_pipeline():
    default = njit(_loop)
    fast = njit(pipeline_class=LoopCompiler)(_loop)
    args = (np.linspace(-1.0, 1.0, 4), np.sin(np.arange(50.0)), np.zeros(50), 0.01)
    a_args, b_args = copy.deepcopy(args), copy.deepcopy(args)
    assert default(*a_args) == fast(*b_args)
    assert np.array_equal(a_args[2], b_args[2]) and np.array_equal(a_args[0], b_args[0])
    (signature,) = default.signatures
    assert _masked(default.inspect_llvm(signature)) == _masked(fast.inspect_llvm(signature))
    passes = fast.overloads[signature].metadata["pipeline_times"]["nopython"]
    assert any(InlineSharingScope._name in name for name in passes)
    assert not any(name.endswith("_inline_inlinables") for name in passes)


def test_the_scope_is_copied_again_after_the_pass():
    scope = ir.Scope(None, ir.Loc("f", 1))
    with scopes_shared_by_deepcopy():
        assert copy.deepcopy(scope) is scope
    assert copy.deepcopy(scope) is not scope and "__deepcopy__" not in ir.Scope.__dict__


def test_numbas_inliner_and_block_copies_are_restored_after_the_pass():
    njit(pipeline_class=LoopCompiler)(_loop)(np.zeros(2), np.ones(3), np.zeros(3), 0.1)
    assert inline_closurecall.InlineWorker is not FreshCalleeInliner
    block = ir.Block(ir.Scope(None, ir.Loc("f", 1)), ir.Loc("f", 1))
    assert copy.deepcopy(block) is not block and "__deepcopy__" not in ir.Block.__dict__
    with fresh_callees_not_copied():
        assert inline_closurecall.InlineWorker is FreshCalleeInliner
    assert inline_closurecall.InlineWorker is not FreshCalleeInliner
