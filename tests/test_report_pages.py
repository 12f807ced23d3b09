"""Every page of the report of the default run and of a user's own run (a 150 kW UAV drivetrain,
other ranges, sampled designs, a constraint in degC): text at 8 pt or more (the pages are A4 at
100 %), nothing outside the page, the trace pages drawing and naming a design of the run, numbers
in the units engineers read (CSV headers carry their unit), the validation table paginated with
every row on a page and the summary naming its pages."""

import csv
from pathlib import Path

import numpy as np
import pytest

from clutchlab import config, explore, pipeline, report, store, studies, traces
from clutchlab.report.common import (
    legends_over_data,
    texts_outside,
    texts_outside_cells,
    texts_overprinted,
    texts_too_small,
)

ROOT = Path(__file__).resolve().parents[1]

# what a new user wrote for a 150 kW UAV (engine 6000 rpm, heavier rotor-side inertia, higher
# loads), with their own ranges and sampled designs
UAV = {
    "studies": ["diaphragm_spring", "engagement", "centrifugal", "sprag", "roller"],
    "report": {"title": "150 kW UAV drivetrain: clutch options"},
    "diaphragm_spring": {
        "design": "lhs",
        "samples": 60,
        "seed": 3,
        "parameters": {
            "sheet_thickness": {"min": "2.2 mm", "max": "3.0 mm"},
            "cone_height_ratio": {"min": 1.3, "max": 2.0},
            "max_engine_torque": "240 N*m",
        },
    },
    "engagement": {
        "design": "factorial",
        "constraints": {
            "peak_surface_temperature": {"max": "200 degC"},
            "lockup_time": {"max": "0.5 s"},
        },
        "parameters": {
            "sheet_thickness": {"values": ["2.4 mm", "2.8 mm"]},
            "ramp_time": {"values": ["0.1 s", "0.2 s", "0.3 s"]},
            "driven_inertia": {"values": ["0.05 kg*m^2", "0.08 kg*m^2"]},
            "engine_speed": "6000 rpm",
            "load_torque": "120 N*m",
            "cone_height_ratio": 1.5,
        },
    },
    "centrifugal": {
        "design": "sobol",
        "samples": 64,
        "seed": 2,
        "parameters": {
            "pressure_angle": {"min": "25 deg", "max": "55 deg"},
            "friction_coefficient": {"min": 0.3, "max": 0.5},
            "engine_torque": "240 N*m",
            "rated_speed": "6000 rpm",
        },
    },
    "sprag": {
        "design": "factorial",
        "parameters": {
            "torque": {"values": ["300 N*m", "500 N*m", "800 N*m"]},
            "sprags": {"values": [16, 18, 20]},
            "sprag_length": {"values": ["14 mm", "16.891 mm"]},
        },
    },
    "roller": {
        "design": "factorial",
        "parameters": {
            "rollers": {"values": [8, 12]},
            "wedge_angle": {"values": ["9 deg", "11 deg"]},
            "max_torque": "300 N*m",
            "rated_speed": "6000 rpm",
        },
    },
}

# pages drawing the traces (or curves) of one design of the run
TRACE_PAGES = (
    "engagement_traces",
    "engagement_heat",
    "centrifugal_capacity_curves",
    "centrifugal_traces",
    "roller_engagement_trace",
)


def _run(cfg, folder):
    """Every study of a resolved config computed in memory, stored like the workflow stores them:
    result, traces, sensitivity (factorial designs), validation."""
    files, trace_files, sens, vals = {}, {}, {}, []
    for name in cfg["studies"]:
        sec = cfg[name]
        ds = pipeline.run_study(sec)
        tr = traces.compute(ds, sec["options"])
        files[name] = store.write(
            ds.drop_vars([v for v in tr.variables if v in ds]), folder / f"{name}.h5"
        )
        trace_files[name] = store.write(tr, folder / f"{name}_traces.h5")
        if sec["design"] == "factorial":
            outputs = [o.split(":")[0] for o in sec["objectives"]] + list(sec["constraints"])
            sens[name] = store.write(explore.sensitivity(ds, outputs), folder / f"{name}_sens.h5")
        if studies.get(name).validation is not None:
            vals.append(store.write(studies.get(name).validation(), folder / f"{name}_val.h5"))
    return files, trace_files, sens, vals


def _figures(monkeypatch):
    """The figures report.build draws (collected where it closes them)."""
    import matplotlib

    figures = []
    monkeypatch.setattr(report.plt, "close", figures.append)
    monkeypatch.setitem(matplotlib.rcParams, "figure.max_open_warning", 0)  # (kept to check them)
    return figures


@pytest.mark.slow
@pytest.mark.parametrize("which", ["default", "uav"])
def test_every_page_is_legible_and_shows_the_runs_design(which, tmp_path, monkeypatch):
    from clutchlab import hardcases
    from clutchlab.bench import engagement as bench_engagement

    cfg = config.load(ROOT / "config/config.yaml") if which == "default" else config.resolve(UAV)
    files, trace_files, sens, vals = _run(cfg, tmp_path)
    names = list(files)
    cases = store.write(hardcases.to_dataset(hardcases.run(names)), tmp_path / "hard.h5")
    extra = {}
    if which == "default":  # the engagement work-precision page, from a small benchmark run (the
        # numerics pages: tests/test_pipeline.py, on the small run's own)
        bench_engagement.run(tmp_path / "bench", n=50, n_ref=2)
        extra = dict(benchmark_csv=tmp_path / "bench" / "engagement_benchmark.csv")
    figures = _figures(monkeypatch)
    out = tmp_path / "report"
    written = report.build(
        files,
        vals,
        out,
        title=cfg["report"]["title"],
        sensitivity_files=sens,
        hard_cases_file=cases,
        traces_files=trace_files,
        **extra,
    )
    stems = [p.stem for p in written if p.suffix == ".png"]
    run = report.run_stems(names, which == "default", hard_cases=True)
    assert stems[0] == "title" and stems[len(stems) - len(run) + 1 :] == run[1:]
    layout, png = _pdf_layout(stems, figures)
    assert layout[stems[-1]][1] == _pdf_pages(out / "report.pdf")  # every figure accounted for
    for fig in figures:
        label = fig.texts[0].get_text()[:60] if fig.texts else fig.axes[0].get_title()[:60]
        assert not texts_too_small(fig), (label, texts_too_small(fig)[:5])
        assert not texts_outside(fig), (label, texts_outside(fig))
        assert not texts_overprinted(fig), (label, texts_overprinted(fig))
        assert not legends_over_data(fig), (label, legends_over_data(fig))
        assert not texts_outside_cells(fig), (label, texts_outside_cells(fig))
    # the trace pages draw and name the design the run shows, one of its scenarios
    for name in names:
        ds = traces.attach(store.load(files[name]), store.load(trace_files[name]))
        i = int(ds.attrs["shown_index"])
        assert 0 <= i < ds["status"].size
        design = traces.design_text(ds, i)
        assert ds.attrs["shown_design"] == design
        for stem in (s for s in TRACE_PAGES if s.startswith(f"{name}_")):
            text = " ".join(" ".join(_texts(png[stem])).split())
            assert " ".join(design.split()) in text, (stem, design, text[:300])
            assert any(ax.lines for ax in png[stem].axes), stem
    _check_units(out, names)
    # the summary names the pages: each study's, and the validation table's (every row on a page)
    summary = " ".join(" ".join(t.get_text() for t in png["title"].texts).split())
    first, last = layout["validation_table"]
    assert f"table on pages {first}-{last}" in summary or f"table on page {first}" in summary
    for name in names:
        assert f"pages {layout[f'{name}_{report.study_page_stems(name)[0]}'][0]}-" in summary
    rows = sum(
        max(r for r, _ in f.axes[0].tables[0].get_celld())
        for f in figures
        if f.texts and f.texts[0].get_text().startswith("Validation against the source papers (")
    )
    assert rows == sum(v.sizes["row"] for v in map(store.load, vals)) and last > first
    if which == "uav":
        answers = " ".join(" ".join(_texts(png["engagement_answers"])).split())
        assert "peak_surface_temperature max: 200 degC" in answers
    _check_details(png, files, which)


def _check_details(png, files, which):
    """Sensitivity tick labels break at underscores, never inside a word; the heat page's pale
    markers have a dark edge; the answers pages' axes span the feasible designs (a far infeasible
    one does not squeeze the front); an answer at the edge of a factor's range says so."""
    for stem in (s for s in png if s.endswith("_sensitivity")):
        for ax in png[stem].axes:
            for label in ax.get_yticklabels():
                lines = label.get_text().split("\n")
                assert all(line.endswith(("_", " ")) for line in lines[:-1]), (stem, lines)
    if "engagement_heat" in png:
        edges = [c.get_edgecolor() for ax in png["engagement_heat"].axes for c in ax.collections]
        assert any(len(e) and (np.asarray(e)[:, :3] < 0.5).all() for e in edges)
    for name in files:
        ds = store.load(files[name])
        feas = explore.flat(ds, "feasible").astype(bool)
        objectives = [o.split(":")[0] for o in ds["pareto_rank"].attrs["objectives"].split()]
        if feas.sum() < 2 or len(objectives) != 2:
            continue
        from clutchlab import display

        ax = next(
            a
            for a in png[f"{name}_answers"].axes
            if a.get_xlabel().endswith(("(minimised)", "(maximised)"))
        )
        for lim, o in ((ax.get_xlim(), objectives[0]), (ax.get_ylim(), objectives[1])):
            v = display.unit_of(ds, o)(explore.flat(ds, o)[feas])
            span = np.ptp(v) or abs(v.max()) or 1.0
            assert v.min() - 0.06 * span <= lim[0] and lim[1] <= v.max() + 0.06 * span, (name, o)
    if which == "default":  # every sprag front design at 22 sprags, the top of 14-22
        text = " ".join(" ".join(_texts(png["sprag_answers"])).split())
        assert "upper edge of the sprags range" in text and "widen the range of sprags" in text


def _texts(fig):
    from matplotlib.text import Text

    return [t.get_text() for t in fig.findobj(Text) if t.get_visible()]


def _is_table_part(fig):
    return bool(fig.texts) and "(page " in fig.texts[0].get_text()


def _pdf_layout(stems, figures):
    """(stem -> its first and last page of the PDF, stem -> the figure of its PNG) from the figures
    report.build drew, in order: the studies' pages (each page's PNG figure, then a table's A4
    pages), the run's pages, then the summary; ``stems``: the PDF's order (the summary first)."""
    drawn = stems[1:] + stems[:1]
    k, png, parts_of = 0, {}, {}
    for s in drawn:
        png[s] = figures[k]
        k += 1
        parts = 0
        while k < len(figures) and _is_table_part(figures[k]):
            parts, k = parts + 1, k + 1
        parts_of[s] = max(parts, 1)
    assert k == len(figures)
    page, layout = 0, {}
    for s in stems:
        layout[s] = (page + 1, page + parts_of[s])
        page += parts_of[s]
    return layout, png


def _pdf_pages(path):
    data = path.read_bytes()
    return data.count(b"/Type /Page\n") + data.count(b"/Type /Page ") + data.count(b"/Type /Page>")


def _check_units(out, names):
    """The CSV headers carry the units engineers read: temperatures in degC, lengths in mm,
    angles in deg, stresses in MPa, times in ms; never K, m, rad or Pa."""
    headers = []
    for name in names:
        with open(out / f"{name}_pareto.csv") as fh:
            headers += next(csv.reader(fh))
    units = {h.split(" [")[1].rstrip("]") for h in headers if " [" in h}
    assert not units & {"K", "m", "rad", "Pa", "s", "N m", "J", "rad/s"}, units
    by_name = {h.split(" [")[0]: h.split(" [")[1].rstrip("]") for h in headers if " [" in h}
    expect = {
        "sheet_thickness": "mm",
        "sprag_length": "mm",
        "wedge_angle": "deg",
        "pressure_angle": "deg",
        "contact_stress": "MPa",
        "peak_surface_temperature": "degC",
        "lockup_time": "ms",
        "engagement_time": "ms",
        "slip_work": "kJ",
    }
    for n, u in expect.items():
        if n in by_name:
            assert by_name[n] == u, (n, by_name[n])
    assert {"sheet_thickness", "wedge_angle", "contact_stress", "lockup_time"} <= set(by_name)
    with open(out / "validation.csv") as fh:
        rows = list(csv.DictReader(fh))
    assert rows and not {r["units"] for r in rows} & {"Pa", "K", "m", "rad"}
    assert np.isfinite([float(r["computed"]) for r in rows]).all()


def test_validation_table_shows_the_tolerance_it_judged_by():
    """A tolerance of 0.15 reads 0.15 (it read 1e-01 beside errors of 0.11 that pass)."""
    import xarray as xr

    from clutchlab.report.common import validation_table

    v = xr.Dataset(
        {
            "seed": ("row", ["001"]),
            "quantity": ("row", ["q"]),
            "source": ("row", ["Table 1"]),
            "published": ("row", [1.0]),
            "computed": ("row", [1.11]),
            "units": ("row", ["1"]),
            "rel_error": ("row", [0.11]),
            "tolerance": ("row", [0.15]),
            "passed": ("row", [1]),
            "note": ("row", [""]),
        }
    )
    (row,) = validation_table([v]).rows
    assert row[7] == "0.15" and row[6] == "1.10e-01" and row[8] == "yes"


def test_a_noise_draw_is_named_by_its_deviations():
    """A noise draw is named as one, 'noise draw 1' ('noise = 1' read as a value), with its
    deviations: 'friction_coefficient +20 %'."""
    import xarray as xr

    from clutchlab.report.common import fixed_text

    sub = xr.Dataset(
        {"friction_coefficient_noise": ((), 0.2, {"relative": 1, "units": "1"})},
        coords={"noise": 1, "shoes": 3.0},
    )
    assert (
        fixed_text(sub, ["shoes", "noise"])
        == "shoes = 3, noise draw 1 (friction_coefficient +20 %)"
    )
