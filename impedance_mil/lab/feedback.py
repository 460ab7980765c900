"""The source of the force feedback w (report Section 8.3.2): one vocabulary for the CLI, campaigns and files.

=========  ========================  =======================================  ==============
name       member                    w fed to the controller (and the VS)     u_w path
=========  ========================  =======================================  ==============
``lc``     ``LOAD_CELLS``            reaction load cells                      on
``fe``     ``FORCE_EQUILIBRIUM``     force equilibrium ``m_st z - A_p dP``    on
``none``   ``NONE``                  load cells (tracking only)               off (u_w = 0)
=========  ========================  =======================================  ==============

The names are those of ``imil simulate/track --feedback``, of the run files
and of campaign files.  Campaign files written before the vocabulary was
shared spelled ``load_cells`` and ``force_equilibrium``; :meth:`Feedback.parse`
still reads them (:data:`LEGACY_NAMES`).
"""

from __future__ import annotations

from enum import StrEnum

from ..errors import ConfigError

#: Older spellings (campaign files), by current name.
LEGACY_NAMES = {"load_cells": "lc", "force_equilibrium": "fe"}


class Feedback(StrEnum):
    """Source of w; the value is its name (``lc``, ``fe``, ``none``)."""

    LOAD_CELLS = "lc"
    FORCE_EQUILIBRIUM = "fe"
    NONE = "none"

    @property
    def channel(self) -> str:
        """Lab channel of w (``lc`` or ``fe``; ``none`` still measures with the load cells)."""
        return "fe" if self is Feedback.FORCE_EQUILIBRIUM else "lc"

    @property
    def compensates(self) -> bool:
        """Whether the controller's u_w path is on."""
        return self is not Feedback.NONE

    @classmethod
    def parse(cls, text: str, key: str = "feedback", *, allow_none: bool = True) -> Feedback:
        """The source a name (or an older spelling) stands for.

        Raises
        ------
        ConfigError
            Naming ``key``: not a source, or ``none`` where it is not allowed
            (a MIL run must feed the measured force to the VS).
        """
        name = str(text).strip().lower()
        name = LEGACY_NAMES.get(name, name)
        names = [f.value for f in cls if allow_none or f is not cls.NONE]
        if name not in names:
            choices = (
                "lc, fe or none"
                if allow_none
                else "lc or fe (a MIL run feeds the measured force to the VS; 'none' is for tracking)"
            )
            raise ConfigError(key, choices, text)
        return cls(name)
