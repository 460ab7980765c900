"""numba's compiler pipeline for the compiled loop, with a fast IR inliner (issue 16, goal 4).

The loop (:mod:`impedance_mil.lab.tick`) inlines every stage and kernel at numba-IR
level (``inline="always"``).  numba's ``InlineInlinables`` pass copies the callee's IR
at every call site with :func:`copy.deepcopy`, block by block, and each copied
variable drags a copy of the callee's whole variable scope with it: the cost of an
inline grows as blocks x variables of the callee.  On the first run this pass took
about 60 % of the compile of the loop (86 s of 127 s, measured with numba's
``pipeline_times``, benchmarks/bench_first_run.py); it is numba's known issue
(numba#8989, numba#9204; numba-cuda#689 skips the same copies).

:class:`LoopCompiler` is numba's default nopython pipeline with that one pass
replaced by :class:`InlineSharingScope`, which runs numba's own pass while a
:class:`numba.core.ir.Scope` deep-copies to itself.  The copy of a callee made for
an inline then shares the scope of the callee's IR, which the inliner builds afresh
for each call site and only reads and extends with the inlined names before it is
dropped; the caller's IR and its names are the same as with numba's pass, so the
generated code is the same (the loop's LLVM IR is compared, text for text, in
``tests/lab/test_inline_pipeline.py``) and the results are bit-identical.  The
change lasts while the pass runs, which numba's compiler lock keeps to one
compile at a time; ``pipeline_class`` is numba's public hook for a pipeline.
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager

from numba.core import inline_closurecall, ir
from numba.core.compiler import CompilerBase, DefaultPassBuilder
from numba.core.compiler_machinery import register_pass
from numba.core.untyped_passes import InlineInlinables

#: The hook ``copy.deepcopy`` looks up on a class (set on a class given as an argument).
_DEEPCOPY = "__deepcopy__"


@contextmanager
def _deepcopy_returns_self(cls: type) -> Iterator[None]:
    """Within the block, ``copy.deepcopy`` of an instance of ``cls`` returns the instance itself."""
    had_own = _DEEPCOPY in cls.__dict__
    previous = cls.__dict__.get(_DEEPCOPY)
    setattr(cls, _DEEPCOPY, lambda self, memo: self)
    try:
        yield
    finally:
        if had_own:
            setattr(cls, _DEEPCOPY, previous)
        else:
            delattr(cls, _DEEPCOPY)


def scopes_shared_by_deepcopy():
    """Within the block, ``copy.deepcopy`` of a numba IR scope returns the scope itself."""
    return _deepcopy_returns_self(ir.Scope)


class FreshCalleeInliner(inline_closurecall.InlineWorker):
    """numba's ``InlineWorker``, without the two copies of a callee's IR that is built for one call site.

    numba's ``inline_function`` builds the callee's IR afresh (``run_untyped_passes``)
    and hands it to ``inline_ir``, which deep-copies it twice, block by block: one copy
    to splice into the caller, one unmutated copy to return, which ``InlineInlinables``
    drops.  The fresh IR has no other user, so here ``inline_ir`` splices it in itself
    (``copy.deepcopy`` of a block returns the block while ``inline_ir`` runs; nothing
    else in ``inline_ir`` copies).  With arguments' types (typed inlining, which updates
    type maps from the copy) it is numba's method unchanged.
    """

    def inline_function(self, caller_ir, block, i, function, arg_typs=None):
        if arg_typs is not None:
            return super().inline_function(caller_ir, block, i, function, arg_typs=arg_typs)
        callee_ir = self.run_untyped_passes(function)
        with _deepcopy_returns_self(ir.Block):
            return self.inline_ir(caller_ir, block, i, callee_ir, function.__code__.co_freevars)


@contextmanager
def fresh_callees_not_copied() -> Iterator[None]:
    """Within the block, numba's inliner passes use :class:`FreshCalleeInliner` (they import
    ``InlineWorker`` from its module when they run, the callees' own inliner passes too)."""
    previous = inline_closurecall.InlineWorker
    inline_closurecall.InlineWorker = FreshCalleeInliner
    try:
        yield
    finally:
        inline_closurecall.InlineWorker = previous


@register_pass(mutates_CFG=True, analysis_only=False)
class InlineSharingScope(InlineInlinables):
    """numba's ``InlineInlinables``, run with IR scopes shared by the inliner's copies."""

    _name = "inline_inlinables_sharing_scope"

    def run_pass(self, state) -> bool:
        with scopes_shared_by_deepcopy(), fresh_callees_not_copied():
            return super().run_pass(state)


class LoopCompiler(CompilerBase):
    """numba's nopython pipeline with :class:`InlineSharingScope` in place of ``InlineInlinables``."""

    def define_pipelines(self):
        pm = DefaultPassBuilder.define_nopython_pipeline(self.state)
        pm.passes = [
            (InlineSharingScope if cls is InlineInlinables else cls, text) for cls, text in pm.passes
        ]
        return [pm]


__all__ = [
    "FreshCalleeInliner",
    "InlineSharingScope",
    "LoopCompiler",
    "fresh_callees_not_copied",
    "scopes_shared_by_deepcopy",
]
