"""Headless Chromium (Debian's chromium + chromium-driver) driven by Selenium.

Outside CI a machine without Chromium skips the browser tests with a message saying how
to install it; in CI (``CI`` set) a missing browser fails them: .ci/run installs it.
"""

from __future__ import annotations

import os
import shutil
import tempfile
from pathlib import Path

import pytest

CHROMIUM = ("/usr/bin/chromium", "/usr/bin/chromium-browser")
DRIVER = ("/usr/bin/chromedriver",)
FLAGS = ("--headless=new", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
         "--disable-background-networking", "--disable-component-update", "--disable-sync",
         "--disable-dev-shm-usage", "--window-size=1400,1000")
MISSING = ("headless Chromium is needed for the report's browser tests: "
           "apt-get install -y chromium chromium-driver, and pip install -e '.[view,test]' "
           "(for selenium)")


def _first(paths) -> str | None:
    return next((p for p in paths if Path(p).exists()), None)


def require_browser() -> tuple[str, str]:
    """The browser and driver paths; fail in CI, skip elsewhere, when they are missing."""
    browser, driver = _first(CHROMIUM), _first(DRIVER) or shutil.which("chromedriver")
    try:
        import selenium  # noqa: F401
    except ImportError:
        browser = None
    if browser and driver:
        return browser, driver
    if os.environ.get("CI"):
        pytest.fail(MISSING)
    pytest.skip(MISSING)


def start_chromium():
    """A fresh headless Chromium with its own profile directory (removed by ``stop``)."""
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service

    browser, driver = require_browser()
    profile = tempfile.mkdtemp(prefix="stampc-chromium-")
    options = webdriver.ChromeOptions()
    options.binary_location = browser
    for flag in (*FLAGS, f"--user-data-dir={profile}"):
        options.add_argument(flag)
    chrome = webdriver.Chrome(service=Service(executable_path=driver), options=options)
    chrome.stampc_profile = profile
    return chrome


def stop(chrome) -> None:
    profile = chrome.stampc_profile
    chrome.quit()
    shutil.rmtree(profile, ignore_errors=True)


def load_report(chrome, path: Path, timeout: float = 30.0) -> float:
    """Open the report and wait until its script ran and the graph was drawn; the
    seconds from navigation start to that point (the browser's own clock)."""
    from selenium.webdriver.support.ui import WebDriverWait

    chrome.get(path.resolve().as_uri())
    WebDriverWait(chrome, timeout).until(
        lambda d: d.execute_script("return document.body.dataset.graphDrawn === 'true'"))
    return chrome.execute_script("return performance.now() / 1000")
