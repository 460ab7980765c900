"""The HTML pages in a real headless browser: they load without console errors and every figure renders.

Chromium and chromedriver come from Debian's packages (``scripts/install-browser.sh``).
With ``CI=true`` a missing browser fails the test; elsewhere the test is skipped.
The pages are served from a localhost http.server, like a user opening them.
"""

from __future__ import annotations

import functools
import http.server
import os
import shutil
import tempfile
import threading

import numpy as np
import pytest

from impedance_mil.campaign import InlineExecutor, load_campaign, run_campaign
from impedance_mil.campaign.claims import AGREE, CLAIMS, Claim, Curve
from impedance_mil.report.html import RunView, html_page, render_run_html, write_html
from impedance_mil.report.reproduction import write_reproduction_report

webdriver = pytest.importorskip("selenium.webdriver", reason="selenium (test-only dependency) missing")

CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser") or shutil.which("google-chrome")
CHROMEDRIVER = shutil.which("chromedriver")
FLAGS = (
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--disable-dev-shm-usage",
    "--window-size=1200,900",
)


def _require_browser() -> None:
    if CHROMIUM and CHROMEDRIVER:
        return
    reason = "chromium/chromedriver not installed (run scripts/install-browser.sh)"
    if os.environ.get("CI", "").lower() == "true":
        pytest.fail(reason)
    pytest.skip(reason)


@pytest.fixture(scope="module")
def browser():
    _require_browser()
    os.environ.setdefault("SE_AVOID_STATS", "true")
    profile = tempfile.mkdtemp(prefix="imil-chromium-")
    options = webdriver.ChromeOptions()
    options.binary_location = CHROMIUM
    for flag in FLAGS:
        options.add_argument(flag)
    options.add_argument(f"--user-data-dir={profile}")
    options.set_capability("goog:loggingPrefs", {"browser": "ALL"})
    driver = webdriver.Chrome(options=options, service=webdriver.ChromeService(executable_path=CHROMEDRIVER))
    try:
        yield driver
    finally:
        driver.quit()
        shutil.rmtree(profile, ignore_errors=True)


class _QuietHandler(http.server.SimpleHTTPRequestHandler):
    def log_message(self, format, *args):  # noqa: A002 - signature of the base class
        pass


@pytest.fixture
def served(tmp_path):
    """Serve tmp_path on localhost; yield the base URL."""
    handler = functools.partial(_QuietHandler, directory=str(tmp_path))
    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), handler)
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    try:
        yield f"http://127.0.0.1:{server.server_address[1]}"
    finally:
        server.shutdown()
        server.server_close()


# Facts about the page, read in the browser.
PROBE = """
const imgs = Array.from(document.images).map(i => [i.complete, i.naturalWidth, i.naturalHeight, i.alt]);
const svgs = Array.from(document.querySelectorAll('svg')).map(s => {
  const r = s.getBoundingClientRect(); return [r.width, r.height]; });
const external = performance.getEntriesByType('resource').map(e => e.name);
return {imgs: imgs, svgs: svgs, external: external, scripts: document.scripts.length,
        title: document.title, h1: document.querySelector('h1').textContent};
"""


def _check_page(driver, url: str) -> dict:
    driver.get_log("browser")  # drop earlier entries
    driver.get(url)
    facts = driver.execute_script(PROBE)
    errors = [e for e in driver.get_log("browser") if e["level"] in ("SEVERE", "ERROR")]
    assert errors == [], errors
    assert facts["scripts"] == 0 and facts["external"] == []
    for complete, width, height, alt in facts["imgs"]:
        assert complete and width > 0 and height > 0, alt
    for width, height in facts["svgs"]:
        assert width > 0 and height > 0
    return facts


def test_run_page_renders_every_figure(browser, served, tmp_path):
    t = np.arange(0.0, 8.0, 0.0005)
    a_g = 150.0 * np.sin(2 * np.pi * 1.5 * t) * np.exp(-0.3 * t)
    channels = {
        "t": t,
        "a_g": a_g,
        "z": 1.03 * a_g,
        "z_vs": 0.8 * a_g,
        "x": 0.01 * np.sin(2 * np.pi * 1.5 * t),
        "w": -20.0 * a_g,
        "u_w": 1e-3 * a_g,
    }
    view = RunView.from_channels(
        channels, title="Synthetic run", metrics={"nrmse": 0.03}, config={"table": {"Kp": 0.001}}, m_vs=5.18
    )
    write_html(tmp_path / "run.html", render_run_html(view))
    facts = _check_page(browser, f"{served}/run.html")
    # histories, spectra, force-displacement
    assert len(facts["imgs"]) == 3 and facts["title"] == "Synthetic run"


def _two_curves(rows):
    x = tuple(rows.values("stiffness"))
    return (
        AGREE,
        "two curves",
        (
            Curve("toolkit", x, tuple(rows.values("frequency_hz"))),
            Curve("report", x, tuple(rows.values("frequency_hz")), "target"),
        ),
        "k [lbf/in]",
        "f [Hz]",
        True,
    )


def test_reproduction_page_renders_every_figure(browser, served, tmp_path):
    body = (
        '[campaign]\nname = "sd"\nkind = "selftest"\n[base]\nmass = "5600 lb"\n'
        '[[study]]\nname = "table-9.1"\nzip = { stiffness = [322, 894, 1753], damping = [41, 57, 64] }\n'
    )
    (tmp_path / "sd.toml").write_text(body)
    run_campaign(load_campaign(tmp_path / "sd.toml"), tmp_path / "camp", InlineExecutor())
    extra = Claim("test-claim", "9.2", "statement", "selftest", "table-9.1", "test", _two_curves)
    result = write_reproduction_report([tmp_path / "camp"], tmp_path / "repro.html", CLAIMS + (extra,))
    assert result.agree == 1 and result.not_run == len(CLAIMS)
    facts = _check_page(browser, f"{served}/repro.html")
    # The claim figure is inline SVG: one, with a size.
    assert len(facts["imgs"]) == 0 and len(facts["svgs"]) == 1


def test_the_probe_sees_a_broken_figure(browser, served, tmp_path):
    """The checks above can fail: a truncated PNG has no natural width."""
    write_html(
        tmp_path / "broken.html",
        html_page("broken", ['<img src="data:image/png;base64,iVBORw0KGgo=" alt="truncated">']),
    )
    with pytest.raises(AssertionError, match="truncated"):
        _check_page(browser, f"{served}/broken.html")
