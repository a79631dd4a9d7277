"""Every kind of report.html, opened in a real browser (headless Debian Chromium).

The reports are self-contained pages (images inlined as base64). For each kind (one calibration,
a calibration from several samples, an fe-demo run, an fe-demo band run) the page is loaded from
its file and checked as a reader's browser sees it: every image decodes (``naturalWidth > 0``),
no request leaves the file (Chromium's own network log), and the console shows no error. One
screenshot is kept as a test artefact under ``build/test-artifacts/``.

Needs Debian's ``chromium`` and ``chromium-driver`` (``.ci/run`` installs them) and selenium
(test extra); skips, saying so, where they are missing. Selenium is pointed at the system
chromedriver and browser, so it never downloads one.
"""

import json
import shutil
from pathlib import Path

import pytest

from fe_demo.cli import main as fe_demo
from halfspace_calib.cli import main as halfspace_calib

ROOT = Path(__file__).resolve().parents[1]
ARTIFACTS = ROOT / "build" / "test-artifacts"
CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")
CHROMEDRIVER = shutil.which("chromedriver")
SCAN = ROOT / "tests" / "data" / "metropro-1.dat"

CALIB = [
    "--grid", "32",
    "--pressures", "2e7,1e8,3e8,5e8,7e8",
    "--reload-fractions", "0.25,0.5,0.8",
    "--heldout-tol", "0.5",  # a toy grid: the acceptance is tested in test_failed_fit
    "--quiet",
]  # fmt: skip
FE = ["--nr", "6", "--increments", "6", "--vtu-every", "0", "--quiet"]


@pytest.fixture(scope="module")
def driver(tmp_path_factory):
    missing = [
        what
        for what, found in (
            ("chromium (the browser, Debian's chromium)", CHROMIUM),
            ("chromedriver (Debian's chromium-driver)", CHROMEDRIVER),
        )
        if found is None
    ]
    if missing:
        pytest.skip(f"not installed: {' and '.join(missing)} (.ci/run installs them)")
    webdriver = pytest.importorskip("selenium.webdriver")
    from selenium.webdriver.chrome.service import Service

    opts = webdriver.ChromeOptions()
    opts.binary_location = CHROMIUM
    for flag in (
        "--headless=new",
        "--no-sandbox",  # CI runs as root
        "--disable-gpu",
        "--disable-quic",
        "--no-first-run",
        "--disable-background-networking",
        "--disable-component-update",
        "--disable-sync",
        "--disable-dev-shm-usage",
        "--window-size=1200,1600",
        f"--user-data-dir={tmp_path_factory.mktemp('chromium-profile')}",
    ):
        opts.add_argument(flag)
    opts.set_capability("goog:loggingPrefs", {"browser": "ALL", "performance": "ALL"})
    drv = webdriver.Chrome(service=Service(executable_path=CHROMEDRIVER), options=opts)
    drv.set_page_load_timeout(60)
    drv.get("about:blank")
    yield drv
    drv.quit()


@pytest.fixture(scope="module")
def reports(tmp_path_factory):
    """One report.html of each kind, made by the commands at coarse settings."""
    base = tmp_path_factory.mktemp("reports")
    out = {
        "calibration": base / "calibration",
        "samples": base / "samples",
        "fe-demo": base / "fe",
        "band": base / "band",
    }
    assert halfspace_calib([*CALIB, "--out", str(out["calibration"])]) == 0
    assert (
        halfspace_calib(
            [
                *CALIB,
                "--workpiece",
                str(SCAN),
                "--patches",
                "4",
                "--bootstrap",
                "60",
                "--out",
                str(out["samples"]),
            ]
        )  # fmt: skip
        == 0
    )
    params = out["calibration"] / "params.json"
    assert fe_demo(["upsetting", "--params", str(params), *FE, "--out", str(out["fe-demo"])]) == 0
    band_params = out["samples"] / "params.json"
    assert (
        fe_demo(
            ["upsetting", "--params", str(band_params), "--band", *FE, "--out", str(out["band"])]
        )
        == 0
    )
    return {kind: folder / "report.html" for kind, folder in out.items()}


def _requests(driver):
    """URLs of every request a web page made, from Chromium's network log.

    The browser's own pages (``chrome://`` documents such as its start page) are not the
    report's and are left out; everything a ``file:`` or other document asked for counts.
    """
    urls = []
    for entry in driver.get_log("performance"):
        msg = json.loads(entry["message"])["message"]
        if msg.get("method") == "Network.requestWillBeSent":
            params = msg["params"]
            if not params.get("documentURL", "").startswith("chrome://"):
                urls.append(params["request"]["url"])
    return urls


def _problems(driver, page):
    """What a reader's browser finds wrong with ``page``: undecoded or outside images, requests
    leaving the file, console errors, no title (an empty list for a good page)."""
    driver.get_log("performance")  # drop what earlier pages logged
    driver.get_log("browser")
    url = page.as_uri()
    driver.get(url)
    problems = []
    images = driver.execute_script(
        "return Array.from(document.images).map(i => "
        "[i.complete, i.naturalWidth, i.naturalHeight, i.src.slice(0, 40)]);"
    )
    if not images:
        problems.append("no image")
    for complete, width, height, src in images:
        if not (complete and width > 0 and height > 0):
            problems.append(f"image did not decode: {src}")
        if not src.startswith("data:image/"):
            problems.append(f"image not inlined: {src}")
    outside = [u for u in _requests(driver) if u != url and not u.startswith("data:")]
    if outside:
        problems.append(f"requests left the file: {outside}")
    errors = [e for e in driver.get_log("browser") if e["level"] in ("SEVERE", "ERROR")]
    if errors:
        problems.append(f"console errors: {errors}")
    if not driver.title:
        problems.append("no title")
    return problems


def test_the_check_catches_a_page_that_reaches_out(driver, tmp_path):
    """The checks above can fail: an outside image, a broken image and a script error."""
    bad = tmp_path / "bad.html"
    bad.write_text(
        "<!doctype html><html><head><title>bad</title></head><body>"
        '<img src="http://127.0.0.1:9/outside.png">'
        '<img src="data:image/png;base64,AAAA">'
        "<script>undefined_function_of_a_broken_page();</script></body></html>"
    )
    problems = " | ".join(_problems(driver, bad))
    assert "requests left the file" in problems and "127.0.0.1:9/outside.png" in problems
    assert "image did not decode: data:image/png" in problems
    assert "image not inlined: http://127.0.0.1:9" in problems
    assert "console errors" in problems and "undefined_function_of_a_broken_page" in problems


@pytest.mark.parametrize("kind", ["calibration", "samples", "fe-demo", "band"])
def test_report_renders_in_chromium(kind, reports, driver):
    page = reports[kind]
    assert page.is_file()
    problems = _problems(driver, page)
    assert not problems, f"{kind}: {problems}"
    if kind == "samples":  # one screenshot kept for a reader of the CI run
        ARTIFACTS.mkdir(parents=True, exist_ok=True)
        shot = ARTIFACTS / "report_samples.png"
        assert driver.save_screenshot(str(shot))
        assert shot.stat().st_size > 10_000
        print(f"screenshot: {shot}")
