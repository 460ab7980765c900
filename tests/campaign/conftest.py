"""Shared fixtures for the campaign tests: small campaign files written on the fly."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import pytest

#: The three SD isolators of Table 9.1 (m_vs + m_ps = 5600 lb) as a selftest campaign.
SD_CAMPAIGN = """
[campaign]
name = "sd"
kind = "selftest"
[base]
mass = "5600 lb"
[[study]]
name = "table-9.1"
zip = { stiffness = [322, 894, 1753], damping = [41, 57, 64] }
"""


@pytest.fixture
def make_campaign(tmp_path: Path) -> Callable[..., Path]:
    """Return ``make(body, name="c.toml") -> Path`` writing a campaign file in tmp_path."""

    def make(body: str, name: str = "c.toml") -> Path:
        path = tmp_path / name
        path.write_text(body, encoding="utf-8")
        return path

    return make


@pytest.fixture
def sd_campaign(make_campaign: Callable[..., Path]) -> Path:
    """The three SD isolators of Table 9.1 as a selftest campaign file."""
    return make_campaign(SD_CAMPAIGN, "sd.toml")
