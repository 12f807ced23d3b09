"""Explorer pages in a real browser: open them in headless Chromium and measure (not a unit test).

``python -m clutchlab.bench.explorer OUT.csv PAGE.html ...`` opens each explorer
(:mod:`clutchlab.report.explorer`) in Debian's headless Chromium through chromedriver (Selenium;
no browser is downloaded), each in a fresh browser, ``--repeat`` times (default 1), and writes per
opening: the page's size on disk, the designs it holds, the time from the start of navigation
until plotly.js starts, until the page's script starts (plotly.js read), until the parallel
coordinates and the scatter are drawn and until the frame after is drawn (``open_s``), the CPU
time of Chromium's renderer, GPU and browser processes over the opening (software WebGL runs in
the GPU process), the time of a brush through the page's API (a range on the first axis until the
count and the scatter are redrawn), the time of a brush drawn with the mouse (from the button's
release until the count and the scatter are redrawn), and the load average before each opening.
It saves a screenshot of each page as drawn beside ``OUT.csv``. WebGL is Chromium's software
renderer (SwiftShader): a machine with a GPU draws faster.

``python -m clutchlab.bench.explorer --sizes OUT.csv RESULT.h5 N1 N2 ...`` writes the explorer
of one stored result at each page size (designs held) into a temporary folder and measures each:
how many designs a page handles fluently (:data:`clutchlab.report.explorer.MAX_DESIGNS`).
"""

from __future__ import annotations

import argparse
import contextlib
import os
import shutil
import tempfile
import time
from pathlib import Path

from ._common import write_rows

#: Chromium's flags: headless, software WebGL (SwiftShader; no GPU on a CI machine), no network
#: or background work of its own (a fresh profile per browser: no cache between openings)
FLAGS = (
    "--headless=new",
    "--no-sandbox",
    "--disable-dev-shm-usage",
    "--use-gl=angle",
    "--use-angle=swiftshader-webgl",
    "--enable-unsafe-swiftshader",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--window-size=1600,1300",
)


def chromium() -> tuple[str, str] | None:
    """(chromium, chromedriver) paths of the machine's browser, or None where it has none."""
    browser = shutil.which("chromium") or shutil.which("chromium-browser")
    driver = shutil.which("chromedriver")
    return (browser, driver) if browser and driver else None


@contextlib.contextmanager
def browser():
    """A headless Chromium driven by Selenium (console messages kept for ``get_log``), with a
    new profile folder of its own, removed afterwards."""
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service

    found = chromium()
    if found is None:
        raise RuntimeError("no chromium and chromedriver on this machine (apt: chromium-driver)")
    profile = tempfile.mkdtemp(prefix="clutchlab-chromium-")
    options = webdriver.ChromeOptions()
    options.binary_location = found[0]
    options.page_load_strategy = "none"  # a large page draws for long: wait for its API instead
    for flag in (*FLAGS, f"--user-data-dir={profile}"):
        options.add_argument(flag)
    options.set_capability("goog:loggingPrefs", {"browser": "ALL"})
    try:
        driver = webdriver.Chrome(service=Service(found[1]), options=options)
        driver.set_script_timeout(300)
        driver.command_executor.client_config.timeout = 600  # a busy page answers late
        try:
            yield driver
        finally:
            driver.quit()
    finally:
        shutil.rmtree(profile, ignore_errors=True)


def cpu_seconds(driver) -> dict:
    """CPU time (user + system) of each of the browser's processes so far [s], by kind
    (``renderer``, ``gpu``, ``browser`` for the browser process and its helpers); empty without
    psutil."""
    try:
        import psutil
    except ImportError:
        return {}
    out = {"renderer": 0.0, "gpu": 0.0, "browser": 0.0}
    try:
        procs = psutil.Process(driver.service.process.pid).children(recursive=True)
    except psutil.Error:
        return {}
    for p in procs:
        with contextlib.suppress(psutil.Error):
            cmd = p.cmdline()
            kind = (
                "renderer"
                if "--type=renderer" in cmd
                else "gpu"
                if "--type=gpu-process" in cmd
                else "browser"
            )
            t = p.cpu_times()
            out[kind] += t.user + t.system
    return out


def open_page(driver, path, timeout=300.0) -> dict:
    """Open an explorer page and wait until it is drawn (its API ready); its timings [ms from the
    start of navigation] as the page marked them (:func:`timings`)."""
    uri = Path(path).resolve().as_uri()
    driver.get(uri)
    end = time.monotonic() + timeout
    script = "return location.href === arguments[0] && !!window.clutchlabExplorer;"
    while not driver.execute_script(script, uri):
        if time.monotonic() > end:
            raise TimeoutError(f"{path}: the explorer's script did not start within {timeout} s")
        time.sleep(0.2)
    driver.execute_async_script(
        "const done = arguments[arguments.length - 1], e = window.clutchlabExplorer;"
        "(function wait() { if (e.ready) done(true); else setTimeout(wait, 20); })();"
    )
    return timings(driver)


def timings(driver) -> dict:
    """The page's marks [ms from the start of navigation]: ``plotly`` (plotly.js starts),
    ``script`` (the page's script starts: plotly.js read), ``data`` (the designs decoded),
    ``parcoords``, ``scatter`` (drawn), ``drawn`` (the frame after both; a page without these
    marks, of an earlier clutchlab: its ``startMs`` as ``script`` and ``drawn`` the frame after
    its ``readyMs``)."""
    return driver.execute_async_script(
        "const done = arguments[arguments.length - 1], e = window.clutchlabExplorer;"
        "if (e.timings) { done(e.timings()); return; }"
        "requestAnimationFrame(() => requestAnimationFrame(() =>"
        "  done({script: e.startMs, drawn: performance.now()})));"
    )


def set_range(driver, axis, lo, hi) -> int:
    """Brush ``axis`` to [lo, hi] (display units) through the page's API; the designs left."""
    return driver.execute_async_script(
        "const done = arguments[arguments.length - 1];"
        "window.clutchlabExplorer.setRange(arguments[0], arguments[1], arguments[2])"
        ".then(done, (e) => done('error: ' + e));",
        axis, lo, hi,
    )  # fmt: skip


def brush_ms(driver) -> float:
    """Time of a brush through the page's API on the first axis (its middle half) until the page
    has redrawn [ms]; the range is removed again afterwards."""
    return driver.execute_async_script(
        "const done = arguments[arguments.length - 1];"
        "const e = window.clutchlabExplorer, pc = document.getElementById('parcoords');"
        "const r = pc.data[0].dimensions[0].range, w = r[1] - r[0];"
        "const t0 = performance.now();"
        "e.setRange(e.axes()[0], r[0] + 0.25 * w, r[0] + 0.75 * w)"
        ".then(() => requestAnimationFrame(() => {"
        "  const t = performance.now() - t0; e.clearRanges().then(() => done(t)); }));"
    )


def drag_ms(driver) -> float:
    """Time of a brush drawn with the mouse on the first axis (its middle half), from the
    button's release until the count and the scatter are redrawn and the frame after [ms]."""
    from selenium.webdriver.common.action_chains import ActionChains

    before = driver.execute_script(  # count the scatter's redraws (the page's Plotly.react)
        "const e = window.clutchlabExplorer; e.released = null;"
        "window.addEventListener('mouseup', () => { e.released = performance.now(); },"
        " {capture: true, once: true});"
        "if (!window.Plotly.clutchlabReacts) {"
        "  const react = window.Plotly.react; window.Plotly.clutchlabReacts = 0;"
        "  window.Plotly.react = function () { return react.apply(this, arguments)"
        "    .then((gd) => { window.Plotly.clutchlabReacts++; return gd; }); };"
        "}"
        "return window.Plotly.clutchlabReacts;"
    )
    brush = driver.execute_script(
        "return document.querySelectorAll('#parcoords .axis-brush .background')[0];"
    )
    height = driver.execute_script("return arguments[0].getBoundingClientRect().height;", brush)
    chain = ActionChains(driver).move_to_element_with_offset(brush, 0, int(-0.25 * height))
    chain.click_and_hold().move_by_offset(0, int(0.5 * height)).release().perform()
    return driver.execute_async_script(
        "const done = arguments[arguments.length - 1], e = window.clutchlabExplorer;"
        "const before = arguments[0];"
        "(function wait() {"
        "  if (window.Plotly.clutchlabReacts > before && e.released !== null) {"
        "    requestAnimationFrame(() => done(performance.now() - e.released));"
        "  } else setTimeout(wait, 5);"
        "})();",
        before,
    )


def _row(driver, page, t, cpu0, cpu1, load) -> dict:
    """One opening's figures (times in s)."""
    api = "return window.clutchlabExplorer."
    row = {
        "page": Path(page).name,
        "megabytes": round(os.path.getsize(page) / 1e6, 2),
        "designs_shown": driver.execute_script(api + "total();"),
        "designs_in_study": driver.execute_script(api + "studySize();"),
        "axes_drawn": len(driver.execute_script(api + "shownAxes();")),
        "load_average": round(load, 1),
    }
    for key in ("plotly", "script", "data", "parcoords", "scatter", "drawn"):
        row[f"{key}_s"] = round(t.get(key, float("nan")) / 1e3, 2)
    row["open_s"] = row.pop("drawn_s")
    for kind in ("renderer", "gpu", "browser"):
        row[f"{kind}_cpu_s"] = round(cpu1.get(kind, float("nan")) - cpu0.get(kind, 0.0), 2)
    return row


def measure(pages, shots=None, repeat=1) -> list[dict]:
    """Open each page ``repeat`` times, each in a fresh headless Chromium, and measure it; with
    ``shots`` (a folder) save a screenshot of each page as drawn, before the brushes
    (``<page>.png``)."""
    rows = []
    for _ in range(int(repeat)):
        for page in pages:
            with browser() as driver:
                driver.get("about:blank")
                time.sleep(1.0)  # the browser's own start-up work settles
                load = os.getloadavg()[0]
                cpu0 = cpu_seconds(driver)
                t = open_page(driver, page)
                cpu1 = cpu_seconds(driver)
                if shots is not None:
                    driver.save_screenshot(str(Path(shots) / f"{Path(page).stem}.png"))
                row = _row(driver, page, t, cpu0, cpu1, load)
                row["api_brush_s"] = round(brush_ms(driver) / 1e3, 2)
                row["mouse_brush_s"] = round(drag_ms(driver) / 1e3, 2)
                rows.append(row)
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
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("out", help="the CSV to write (screenshots beside it)")
    p.add_argument("pages", nargs="+", help="explorer pages; with --sizes: RESULT.h5 N1 N2 ...")
    p.add_argument("--sizes", action="store_true", help="one result at several page sizes")
    p.add_argument("--repeat", type=int, default=1, help="openings of each page")
    args = p.parse_args(argv)
    shots = Path(args.out).parent
    shots.mkdir(parents=True, exist_ok=True)
    if args.sizes:
        with tempfile.TemporaryDirectory() as tmp:
            pages = sizes(args.pages[0], args.pages[1:], tmp)
            write_rows(measure(pages, shots, args.repeat), args.out)
        return
    write_rows(measure(args.pages, shots, args.repeat), args.out)


if __name__ == "__main__":
    main()
