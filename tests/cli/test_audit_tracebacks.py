"""The last two tracebacks of the issue 18 audit (finding 7): one line, exit 2, nothing written."""

from __future__ import annotations

from impedance_mil.plant.linear import MAX_PADE_ORDER


def _one_line_error(r, key: str) -> bool:
    lines = r.stderr.strip().splitlines()
    return r.returncode == 2 and len(lines) == 1 and lines[0].startswith(f"imil: error: {key}: ")


def test_bode_to_an_unknown_image_format(imil, tmp_path):
    r = imil("table", "bode", "-o", "b.xyz", cwd=tmp_path)
    assert _one_line_error(r, "-o") and ".png" in r.stderr and "Traceback" not in r.stderr
    assert list(tmp_path.iterdir()) == []


def test_pade_order_beyond_the_bound(imil):
    r = imil("table", "poles", "--delay", "pade", "--pade-order", "1000")
    assert _one_line_error(r, "pade_order") and f"from 1 to {MAX_PADE_ORDER}" in r.stderr
    assert imil("table", "poles", "--delay", "pade", "--pade-order", str(MAX_PADE_ORDER)).returncode == 0
