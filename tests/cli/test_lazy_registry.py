"""The lazy command registry of ``imil`` (issue 16, goal 1 "Start-up").

``imil --help`` lists every command from ``cli.main.COMMANDS`` without importing the command
modules; each command is imported when it runs.  The table's short help must say what the
command's own docstring says, so the listing cannot drift from the commands.
"""

from __future__ import annotations

import importlib
import subprocess
import sys

import pytest
import typer

from impedance_mil.cli import table, table_figures, table_model, vs, vs_figures
from impedance_mil.cli.main import COMMANDS, LazyGroup, app, load_target
from impedance_mil.cli.table import TABLE_COMMANDS
from impedance_mil.cli.vs import VS_COMMANDS
from impedance_mil.plant import default_table_path

#: An LTI table file (a [model] section) shipped with the package.
RTHS_TABLE = default_table_path().parent / "rths_benchmark_plant.toml"

try:
    from typer._click.utils import make_default_short_help
except ImportError:  # pragma: no cover - depends on the installed typer
    from click.utils import make_default_short_help  # type: ignore[no-redef]

#: Modules a command that only reads a configuration must not import (issue 16: python-control
#: 1.9 s, matplotlib, numba kernels, dask, pandas/pyarrow).
HEAVY = ("control", "matplotlib", "numba", "dask", "distributed", "pandas", "pyarrow")

#: Prints the heavy modules and the command modules imported by ``imil ARGS``, after it ran.
PROBE = """
import atexit, sys
def report():
    print(" ".join(sorted(m for m in sys.modules if m.split(".")[0] in {heavy!r}
                          or m.startswith("impedance_mil.cli.") and m != "impedance_mil.cli.main")))
atexit.register(report)
from impedance_mil.cli.main import run
sys.argv = ["imil", *sys.argv[1:]]
run()
"""


def imported_by(*args: str) -> set[str]:
    """The heavy modules and command modules a fresh ``imil ARGS`` imports."""
    done = subprocess.run(
        [sys.executable, "-c", PROBE.format(heavy=set(HEAVY)), *args],
        capture_output=True,
        text=True,
        check=True,
    )
    return set(done.stdout.splitlines()[-1].split())  # the probe's line comes last


def test_help_imports_no_command_module_and_nothing_heavy():
    assert imported_by("--help") == set()


#: What a command that only reads a configuration may not import (issue 16, goal 1): HEAVY,
#: scipy (any of it), h5py, and pint (0.5 s with its registry; the units of the shipped files
#: are read without it, impedance_mil/unit_names.py), which would import dask in pint.compat.
CONFIGURATION_HEAVY = (*HEAVY, "scipy", "h5py", "pint")


#: Prints, after ``imil ARGS`` ran, the modules of CONFIGURATION_HEAVY it imported.
CONFIGURATION_PROBE = """
import atexit, sys
atexit.register(lambda: print(" ".join(sorted(m for m in {heavy!r} if m in sys.modules))))
from impedance_mil.cli.main import run
sys.argv = ["imil", *sys.argv[1:]]
run()
"""

#: The configuration commands, with and without --json, and with --lab or --table FILE.
CONFIGURATION_COMMANDS = [
    ("table", "info"),
    ("table", "info", "--json"),
    ("table", "info", "--table", str(default_table_path())),
    ("table", "info", "--lab", "report", "--json"),
    ("vs", "list"),
    ("vs", "list", "--json"),
    ("vs", "describe", "SD2", "--json"),
    ("lab", "show"),
    ("lab", "show", "--json"),
    ("lab", "show", "--table", str(default_table_path())),
    ("lab", "show", "--lab", "report", "--units", "si"),
    # SI output too: the units these commands print are shown without pint (unit_names.py)
    ("lab", "show", "--units", "si", "--json"),
    ("table", "info", "--units", "si"),
    ("table", "info", "--units", "si", "--json"),
    ("vs", "list", "--units", "si", "--json"),
]


@pytest.mark.parametrize("args", CONFIGURATION_COMMANDS, ids=" ".join)
def test_a_configuration_command_imports_no_heavy_module(args):
    done = subprocess.run(
        [sys.executable, "-c", CONFIGURATION_PROBE.format(heavy=CONFIGURATION_HEAVY), *args],
        capture_output=True,
        text=True,
        check=True,
    )
    assert done.stdout.splitlines()[-1].split() == []  # the probe's line comes last


#: Parts of the library a configuration command does not need (issue 16, goal 1: 0.1-0.15 s of
#: the 0.4-0.45 s of these commands before they were cut): the VS types' registry (the JSON units
#: read it only for a key no other registry names: report/documents.py), the readers of the LTI
#: table kinds (plant/table_kind.py says which kind a file is), the LTI core (transfer functions,
#: the LTI table's model and lab), and the models of optional lab sections.
LAB_NOT_NEEDED = (
    "impedance_mil.virtual.files",
    "impedance_mil.plant.table_files",
    "impedance_mil.plant.lti_table",
    "impedance_mil.systems",
    "impedance_mil.lab.lti_plant",
    "impedance_mil.plant.uncertainty",
    "impedance_mil.specimens.mounting",
    "impedance_mil.signals.limits",
    "impedance_mil.lti",
)
#: `imil table info` reads a table's parameters: the linear model's commands live in cli/table_model.py.
TABLE_NOT_NEEDED = (
    "impedance_mil.virtual.files",
    "impedance_mil.plant.table_files",
    "impedance_mil.plant.linear",
    "impedance_mil.plant.lti_table",
    "impedance_mil.plant.tuning",
    "impedance_mil.systems",
    "impedance_mil.lab.labfile",
)
#: `imil vs list` reads the VS types: neither the table's model nor its parameters.
VS_NOT_NEEDED = (
    "impedance_mil.plant.linear",
    "impedance_mil.plant.table_files",
    "impedance_mil.systems",
    "impedance_mil.plant.parameters",
    "impedance_mil.lab.labfile",
)
NOT_NEEDED = {
    ("lab", "show"): LAB_NOT_NEEDED,
    ("lab", "show", "--json"): LAB_NOT_NEEDED,
    ("table", "info"): TABLE_NOT_NEEDED,
    ("table", "info", "--json"): TABLE_NOT_NEEDED,
    ("vs", "list"): VS_NOT_NEEDED,
    ("vs", "list", "--json"): VS_NOT_NEEDED,
}


@pytest.mark.parametrize("args", list(NOT_NEEDED), ids=" ".join)
def test_a_configuration_command_imports_only_the_library_it_needs(args):
    done = subprocess.run(
        [sys.executable, "-c", CONFIGURATION_PROBE.format(heavy=NOT_NEEDED[args]), *args],
        capture_output=True,
        text=True,
        check=True,
    )
    assert done.stdout.splitlines()[-1].split() == []


#: A lab with the optional sections whose models `imil lab show` imports only when they are given.
FULL_LAB = """[uncertainty]
f_oil_hz = "±5 %"
[dynamics.platen]
mass_fraction = "10 %"
frequency = "150 Hz"
[dynamics.load_cells]
stiffness = "2e6 lbf/in"
"""


@pytest.mark.parametrize(
    "args, needed",
    [
        (("vs", "list"), ("impedance_mil.virtual.files",)),
        (("table", "info", "--table", str(RTHS_TABLE)), ("impedance_mil.plant.table_files",)),
        (("table", "poles"), ("impedance_mil.plant.linear", "impedance_mil.systems")),
        (
            ("lab", "show", "--lab", "FULL_LAB"),
            ("impedance_mil.plant.uncertainty", "impedance_mil.specimens.mounting"),
        ),
    ],
    ids=lambda v: " ".join(a.rsplit("/", 1)[-1] for a in v),
)
def test_the_library_probe_sees_a_module_a_command_needs(args, needed, tmp_path):
    # Not blind: a command that uses a part imports it (an LTI table file needs its reader, the
    # table's poles the LTI core, a lab's [uncertainty] and mounting their models).
    lab = tmp_path / "lab.toml"
    lab.write_text(f'[table]\nfile = "{default_table_path()}"\n' + FULL_LAB)
    args = tuple(str(lab) if a == "FULL_LAB" else a for a in args)
    done = subprocess.run(
        [sys.executable, "-c", CONFIGURATION_PROBE.format(heavy=needed), *args],
        capture_output=True,
        text=True,
        check=True,
    )
    assert done.stdout.splitlines()[-1].split() == list(needed)


def test_the_configuration_probe_sees_a_heavy_module():
    # The probe is not blind: a command that draws imports matplotlib (imil table bode).
    done = subprocess.run(
        [
            sys.executable,
            "-c",
            CONFIGURATION_PROBE.format(heavy=CONFIGURATION_HEAVY),
            "table",
            "bode",
            "--help",
        ],
        capture_output=True,
        text=True,
        check=True,
    )
    assert "matplotlib" in done.stdout.splitlines()[-1].split()


#: A light name of each package, and what importing it may not pull in (issue 16: the package
#: ``__init__`` files import their names on first use, impedance_mil/lazy.py).
LIGHT_NAMES = {
    # pint is imported on the first value it has to read (impedance_mil/config.py)
    "from impedance_mil.plant import TableParameters": (*HEAVY, "pint"),
    "from impedance_mil.lab import RunResult": HEAVY,
    "from impedance_mil.signals import GroundMotion": HEAVY,
    # design and implement import passivity and discretize at the top (names of their own
    # submodules, which cannot be lazy), and those read python-control only when used (LazyModule)
    "import impedance_mil.plant, impedance_mil.lab, impedance_mil.signals, impedance_mil.virtual, "
    "impedance_mil.specimens, impedance_mil.campaign, impedance_mil.design, impedance_mil.implement": (
        *HEAVY,
        "pint",
        "scipy.signal",
        "h5py",
    ),
}


@pytest.mark.parametrize("statement", list(LIGHT_NAMES))
def test_package_inits_import_only_the_names_read(statement):
    probe = (
        f"import sys; {statement}; print(' '.join(m for m in {LIGHT_NAMES[statement]!r} if m in sys.modules))"
    )
    done = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, check=True)
    assert done.stdout.split() == []


@pytest.mark.parametrize(
    "package", ["plant", "lab", "design", "signals", "virtual", "specimens", "campaign", "implement"]
)
def test_every_public_name_of_a_package_resolves(package):
    module = importlib.import_module(f"impedance_mil.{package}")
    for name in module.__all__:
        getattr(module, name)  # an AttributeError or ImportError names the stale entry
    assert set(module.__all__) <= set(dir(module))
    with pytest.raises(AttributeError, match="no_such_name"):
        module.no_such_name  # noqa: B018


def test_help_lists_every_command_in_the_table_order(imil, tmp_path):
    result = imil("--help", cwd=tmp_path)
    listed = [line.split()[0] for line in result.stdout.split("Commands:")[1].splitlines() if line.strip()]
    assert listed == list(COMMANDS)


@pytest.mark.parametrize("name", list(COMMANDS))
def test_table_help_is_the_commands_own_first_sentence(name):
    command = typer.main.get_command(app).commands[name]
    for limit in (45, 80, 10_000):  # the width of a terminal, and no truncation
        assert make_default_short_help(COMMANDS[name].help, limit) == command.get_short_help_str(limit)


def test_every_target_exists():
    for entry in COMMANDS.values():
        assert callable(load_target(entry.target)) or isinstance(load_target(entry.target), typer.Typer)


#: The command groups with a registry of their own (``cli/table.py``, ``cli/vs.py``).
GROUP_REGISTRIES = {"table": TABLE_COMMANDS, "vs": VS_COMMANDS}


@pytest.mark.parametrize(
    ("group", "name"), [(g, n) for g, table in GROUP_REGISTRIES.items() for n in table], ids="-".join
)
def test_a_group_registry_help_is_the_commands_own_first_sentence(group, name):
    command = typer.main.get_command(app).commands[group].commands[name]
    for limit in (45, 80, 10_000):
        assert make_default_short_help(
            GROUP_REGISTRIES[group][name].help, limit
        ) == command.get_short_help_str(limit)


@pytest.mark.parametrize("group", list(GROUP_REGISTRIES))
def test_a_group_lists_its_registry_in_order_and_every_target_exists(group, imil, tmp_path):
    built = typer.main.get_command(app).commands[group]
    assert isinstance(built, LazyGroup)
    assert list(built.commands) == list(GROUP_REGISTRIES[group])
    listed = [
        line.split()[0]
        for line in imil(group, "--help", cwd=tmp_path).stdout.split("Commands:")[1].splitlines()
        if line.strip()
    ]
    assert listed == list(GROUP_REGISTRIES[group])
    for entry in GROUP_REGISTRIES[group].values():
        assert callable(load_target(entry.target))


def test_the_commands_moved_out_of_a_group_module_are_importable_where_they_were():
    assert (table.bode, table.rlocus, vs.loops) == (
        table_figures.bode,
        table_figures.rlocus,
        vs_figures.loops,
    )
    assert (table.poles, table.tf, table.tune) == (table_model.poles, table_model.tf, table_model.tune)
    with pytest.raises(AttributeError, match="no_such_command"):
        table.no_such_command  # noqa: B018


@pytest.mark.parametrize(
    "args", [("table", "info"), ("table", "info", "--json"), ("vs", "list")], ids=" ".join
)
def test_a_command_without_a_lab_does_not_read_the_lab_file_reader(args):
    # The lab-file reader (and through it the sensors' and I/O units' modules, ~0.15 s) loads
    # only when a command reads a lab: the JSON units come from lab/lab_units.py.
    reader = ("impedance_mil.lab.labfile",)
    done = subprocess.run(
        [sys.executable, "-c", CONFIGURATION_PROBE.format(heavy=reader), *args],
        capture_output=True,
        text=True,
        check=True,
    )
    assert done.stdout.splitlines()[-1].split() == []
    with_lab = subprocess.run(
        [sys.executable, "-c", CONFIGURATION_PROBE.format(heavy=reader), *args, "--lab", "report"]
        if args[0] == "table"
        else [sys.executable, "-c", CONFIGURATION_PROBE.format(heavy=reader), "lab", "show"],
        capture_output=True,
        text=True,
        check=True,
    )
    assert with_lab.stdout.splitlines()[-1].split() == list(reader)  # the probe is not blind
