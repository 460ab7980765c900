"""Which kind a table file is: physical (``[table]`` keys) or an LTI table (a ``[model]`` section).

Its own module so that what only asks (``imil lab show``, the ``--units`` default of every
command) does not import the readers of the LTI kinds (:mod:`.table_files`, :mod:`.lti_reader`):
issue 16, start-up.  :mod:`.table_files` re-exports these names.
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import Any

from ..config import read_toml

#: Sections of an LTI table file: the model, and what the table can do (:mod:`.capacity`).
LTI_FILE_SECTIONS = ("model", "capacity")


def is_lti_table_data(data: Mapping[str, Any]) -> bool:
    """Whether a parsed table file is an LTI table (it has a ``[model]`` section)."""
    return "model" in data


def is_lti_table_file(path: str | Path) -> bool:
    """Whether the table file at ``path`` is an LTI table (DataFileError if unreadable)."""
    return is_lti_table_data(read_toml(path))
