#!/usr/bin/env bash
# Install a headless browser for the HTML report tests (tests/report/test_html_browser.py).
#
# Debian's chromium and chromium-driver packages are installed with apt-get
# when either command is missing.  Idempotent: when both are already on PATH,
# nothing is downloaded and the script exits 0.  Needs root (or sudo) to install.
set -euo pipefail

have() { command -v "$1" >/dev/null 2>&1; }

if have chromium && have chromedriver; then
    echo "install-browser: chromium and chromedriver already installed ($(chromium --version 2>/dev/null || echo chromium))"
    exit 0
fi

if [ "$(id -u)" -eq 0 ]; then
    SUDO=""
elif have sudo; then
    SUDO="sudo"
else
    echo "install-browser: need root (or sudo) to install chromium with apt-get" >&2
    exit 1
fi

if ! have apt-get; then
    echo "install-browser: apt-get not found; install chromium and chromedriver with your package manager" >&2
    exit 1
fi

export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends chromium chromium-driver fonts-dejavu-core
echo "install-browser: installed $(chromium --version 2>/dev/null || echo chromium)"
