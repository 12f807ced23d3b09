"""Explorer pages in a real browser: open them in headless Chromium and measure (not a unit test).

``python -m clutchlab.bench.explorer OUT.csv PAGE.html ...`` opens each explorer
(:mod:`clutchlab.report.explorer`) in Debian's headless Chromium through chromedriver (Selenium;
no browser is downloaded) and writes per page: its size on disk, the designs it holds, the time
until the page is drawn and its API ready (from the start of navigation), the share of it spent
reading plotly.js and the data, and the time a brush takes (a range on the first axis, until the
count and the scatter are redrawn), and saves a screenshot of each beside ``OUT.csv``. WebGL is
Chromium's software renderer (SwiftShader): a machine with a GPU draws faster.

``python -m clutchlab.bench.explorer --sizes OUT.csv RESULT.h5 N1 N2 ...`` writes the explorer
of one stored result at each page size (designs held) into a temporary folder and measures each:
how many designs a page handles fluently (:data:`clutchlab.report.explorer.MAX_DESIGNS`).
"""

from __future__ import annotations

import contextlib
import os
import shutil
import sys
import time
from pathlib import Path

from ._common import write_rows

#: Chromium's flags: headless, software WebGL (SwiftShader; no GPU on a CI machine)
FLAGS = (
    "--headless=new",
    "--no-sandbox",
    "--disable-dev-shm-usage",
    "--use-gl=angle",
    "--use-angle=swiftshader-webgl",
    "--enable-unsafe-swiftshader",
    "--window-size=1600,1300",
)


def chromium() -> tuple[str, str] | None:
    """(chromium, chromedriver) paths of the machine's browser, or None where it has none."""
    browser = shutil.which("chromium") or shutil.which("chromium-browser")
    driver = shutil.which("chromedriver")
    return (browser, driver) if browser and driver else None


@contextlib.contextmanager
def browser():
    """A headless Chromium driven by Selenium (console messages kept for ``get_log``)."""
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service

    found = chromium()
    if found is None:
        raise RuntimeError("no chromium and chromedriver on this machine (apt: chromium-driver)")
    options = webdriver.ChromeOptions()
    options.binary_location = found[0]
    options.page_load_strategy = "none"  # a large page draws for long: wait for its API instead
    for flag in FLAGS:
        options.add_argument(flag)
    options.set_capability("goog:loggingPrefs", {"browser": "ALL"})
    driver = webdriver.Chrome(service=Service(found[1]), options=options)
    driver.set_script_timeout(300)
    try:
        yield driver
    finally:
        driver.quit()


def open_page(driver, path, timeout=300.0) -> dict:
    """Open an explorer page and wait for its API; returns its timings [ms from navigation]."""
    driver.get(Path(path).resolve().as_uri())
    end = time.monotonic() + timeout
    script = "const e = window.clutchlabExplorer; return !!(e && e.ready);"
    while not driver.execute_script(script):
        if time.monotonic() > end:
            raise TimeoutError(f"{path}: the explorer was not ready within {timeout} s")
        time.sleep(0.05)
    start, ready = driver.execute_script(
        "const e = window.clutchlabExplorer; return [e.startMs, e.readyMs];"
    )
    return {"ready_ms": ready, "parse_ms": start}


def set_range(driver, axis, lo, hi) -> int:
    """Brush ``axis`` to [lo, hi] (display units) through the page's API; the designs left."""
    return driver.execute_async_script(
        "const done = arguments[arguments.length - 1];"
        "window.clutchlabExplorer.setRange(arguments[0], arguments[1], arguments[2])"
        ".then(done, (e) => done('error: ' + e));",
        axis, lo, hi,
    )  # fmt: skip


def brush_ms(driver) -> float:
    """Time of a brush on the first axis (its middle half) until the page has redrawn [ms]."""
    return driver.execute_async_script(
        "const done = arguments[arguments.length - 1];"
        "const e = window.clutchlabExplorer, pc = document.getElementById('parcoords');"
        "const r = pc.data[0].dimensions[0].range, w = r[1] - r[0];"
        "const t0 = performance.now();"
        "e.setRange(e.axes()[0], r[0] + 0.25 * w, r[0] + 0.75 * w)"
        ".then(() => requestAnimationFrame(() => done(performance.now() - t0)));"
    )


def measure(pages, shots=None) -> list[dict]:
    """Open each page in a fresh headless Chromium and measure it; with ``shots`` (a folder) save
    a screenshot of each page as drawn, before the brush (``<page>.png``)."""
    rows = []
    for page in pages:
        with browser() as driver:
            t = open_page(driver, page)
            if shots is not None:
                driver.save_screenshot(str(Path(shots) / f"{Path(page).stem}.png"))
            n = driver.execute_script("return window.clutchlabExplorer.total();")
            size = driver.execute_script("return window.clutchlabExplorer.studySize();")
            rows.append(
                {
                    "page": Path(page).name,
                    "megabytes": round(os.path.getsize(page) / 1e6, 2),
                    "designs_shown": n,
                    "designs_in_study": size,
                    "ready_s": round(t["ready_ms"] / 1e3, 2),
                    "parse_s": round(t["parse_ms"] / 1e3, 2),
                    "brush_s": round(brush_ms(driver) / 1e3, 2),
                }
            )
        print(rows[-1], flush=True)
    return rows


def sizes(result, counts, folder) -> list[Path]:
    """The explorer of ``result`` at each page size of ``counts``, written into ``folder``."""
    from ..report import explorer

    stem = Path(result).stem
    return [
        explorer.write(result, Path(folder) / f"{stem}_{int(n)}_explorer.html", limit=int(n))
        for n in counts
    ]


def main(argv=None) -> None:
    import tempfile

    argv = list(sys.argv[1:] if argv is None else argv)
    if argv and argv[0] == "--sizes":
        out, result, counts = argv[1], argv[2], argv[3:]
        with tempfile.TemporaryDirectory() as tmp:
            write_rows(measure(sizes(result, counts, tmp)), out)
        return
    out, pages = argv[0], argv[1:]
    write_rows(measure(pages, shots=Path(out).parent), out)


if __name__ == "__main__":
    main()
