"""``imil simulate`` imports what a run needs, not the robust campaign, the plots or the optimizer.

Issue 16: every ``imil simulate`` imported the campaign engine (Dask's ``distributed``, 0.37 s),
matplotlib (for ``--report`` and the motion plots, 0.3 s) and cvxpy (0.17 s); each now loads
when its option is used (``--robust``, ``--report``, an optimized design).  A fresh interpreter
imports the command's module and lists which of them it brought.
"""

from __future__ import annotations

import subprocess
import sys

#: Loaded only by the options that use them.
OPTIONAL = ("distributed", "dask", "matplotlib", "cvxpy", "pandas", "pyarrow")

PROBE = """
import sys
import impedance_mil.cli.simulate
print(" ".join(sorted(m for m in sys.modules if m.split(".")[0] in {optional!r})))
"""


def test_the_simulate_command_module_imports_none_of_the_optional_heavy_modules():
    done = subprocess.run(
        [sys.executable, "-c", PROBE.format(optional=set(OPTIONAL))],
        capture_output=True,
        text=True,
        check=True,
    )
    assert done.stdout.split() == []


RUN_PROBE = """
import atexit, sys
atexit.register(lambda: print("LOADED", *sorted({{m.split(".")[0] for m in sys.modules}} & {optional!r})))
from impedance_mil.cli.main import run
sys.argv = ["imil", "simulate", "--duration", "0.5", "-o", sys.argv[1], "--json"]
run()
"""


def test_a_plain_run_imports_none_of_them_either(tmp_path):
    done = subprocess.run(
        [sys.executable, "-c", RUN_PROBE.format(optional=set(OPTIONAL)), str(tmp_path / "run.h5")],
        capture_output=True,
        text=True,
    )
    assert done.returncode == 0, done.stderr
    assert (tmp_path / "run.h5").is_file()
    assert done.stdout.splitlines()[-1].split() == ["LOADED"]
