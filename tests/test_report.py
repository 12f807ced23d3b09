"""Report built from stored Datasets; validation rows of seed 000."""

import csv
from pathlib import Path

import numpy as np
import pytest

from clutchlab import pipeline, report, store, traces
from clutchlab.config import resolve
from clutchlab.studies import diaphragm_spring

ROOT = Path(__file__).resolve().parents[1]


def test_seed000_validation_rows_all_pass():
    v = diaphragm_spring.validation()
    failed = [
        str(q) for q, ok in zip(v["quantity"].values, v["passed"].values, strict=False) if not ok
    ]
    assert not failed
    assert v.sizes["row"] >= 10


@pytest.mark.parametrize("design", ["factorial", "lhs"])
def test_report_pages(tmp_path, design):
    params = (
        {
            "sheet_thickness": {"values": ["2 mm", "2.4 mm"]},
            "cone_height_ratio": {"values": [1.3, 1.7]},
            "radius_ratio": {"values": [1.25, 1.3]},
        }
        if design == "factorial"
        else {
            "sheet_thickness": {"min": "2 mm", "max": "2.6 mm"},
            "cone_height_ratio": {"min": 1.2, "max": 2.0},
        }
    )
    sec = {"design": design, "parameters": params}
    if design == "lhs":
        sec["samples"] = 50
    cfg = resolve({"studies": ["diaphragm_spring"], "diaphragm_spring": sec})
    spring = store.write(pipeline.run_study(cfg["diaphragm_spring"]), tmp_path / "spring.h5")
    val = store.write(diaphragm_spring.validation(), tmp_path / "val.h5")
    # pages of another config's earlier run into the same folder are removed, other files kept
    (tmp_path / "report").mkdir()
    for stale in ("engagement_heat.png", "engagement_pareto.csv", "notes.txt"):
        (tmp_path / "report" / stale).write_text("an earlier run")
    written = report.build({"diaphragm_spring": spring}, [val], tmp_path / "report")
    left = sorted(p.name for p in (tmp_path / "report").iterdir())
    assert "engagement_heat.png" not in left and "engagement_pareto.csv" not in left
    assert "notes.txt" in left and "diaphragm_spring_pareto.csv" in left
    stems = sorted(p.stem for p in written if p.suffix == ".png")
    assert stems == sorted(report.figure_stems(["diaphragm_spring"]))
    pdf = (tmp_path / "report" / "report.pdf").read_bytes()
    assert (
        pdf.startswith(b"%PDF")
        and pdf.count(b"/Type /Page\n") + pdf.count(b"/Type /Page ") >= len(stems) - 1
    )
    rows = list(csv.DictReader(open(tmp_path / "report" / "validation.csv")))
    # (the spring, damper, spline and capacity rows; the engagement's are the engagement study's)
    assert len(rows) == 11 and all(r["passed"] == "yes" for r in rows)
    if design == "lhs":  # built again (elsewhere): the same bytes, the PDF's too
        two = report.build({"diaphragm_spring": spring}, [val], tmp_path / "two")
        assert [p.name for p in two] == [p.name for p in written]
        for p in written:
            assert (tmp_path / "two" / p.name).read_bytes() == p.read_bytes(), p.name


def test_the_report_joins_each_studys_part_drawn_from_the_result_in_place(tmp_path):
    """A study's part (its pages as PNGs and a PDF part, its record) and the assembly: the PDF is
    the summary, the parts in order, the run's pages; a part drawn from another result than the one
    in place is refused before anything is written."""
    from pypdf import PdfReader

    from clutchlab.verify import ProvenanceError

    def section(sprags):
        return {"design": "factorial", "parameters": {"sprags": {"values": sprags}}}

    grid = {"design": "factorial", "parameters": {}}
    cfg = resolve(
        {
            "studies": ["diaphragm_spring", "sprag"],
            "diaphragm_spring": grid,
            "sprag": section([14, 16]),
        }
    )
    files = {
        n: store.write(pipeline.run_study(cfg[n]), tmp_path / f"{n}.h5", with_checksum=True)
        for n in cfg["studies"]
    }
    out, parts = tmp_path / "report", []
    for name, path in files.items():
        parts.append(tmp_path / "parts" / f"{name}.pdf")
        record = report.study_part(name, path, out, parts[-1], explorer=out / f"{name}_x.html")
        assert [s for s, _ in record["pages"]] == report.study_stems(name)
        assert record["files"] == [f"{name}_pareto.csv"] and (out / f"{name}_x.html").exists()
        assert record["summary"]["title"].startswith(f"Study '{name}': ")
        assert len(PdfReader(parts[-1]).pages) == sum(n for _, n in record["pages"])
        assert all((out / f"{s}.png").exists() for s, _ in record["pages"])
    val = store.write(diaphragm_spring.validation(), tmp_path / "val.h5")
    written = report.assemble(parts, [val], out, title="joined", results=list(files.values()))
    stems = [p.stem for p in written if p.suffix == ".png"]
    assert stems == report.figure_stems(list(files))
    pdf = PdfReader(out / "report.pdf")
    spring_pages = len(PdfReader(parts[0]).pages)
    assert len(pdf.pages) == 1 + spring_pages + len(PdfReader(parts[1]).pages) + 1  # + validation
    assert pdf.metadata["/Title"] == "joined"
    assert "Study 'diaphragm_spring'" in pdf.pages[0].extract_text()
    assert "Diaphragm" in pdf.pages[1].extract_text()  # the first part's first page follows
    # the sprag result recomputed after its part was drawn (another checksum): refused
    other = pipeline.run_study(resolve({"studies": ["sprag"], "sprag": section([18, 20])})["sprag"])
    store.write(other, files["sprag"], with_checksum=True)
    before = (out / "report.pdf").read_bytes()
    with pytest.raises(ProvenanceError, match=r"sprag\.pdf was drawn from another .*sprag\.h5"):
        report.assemble(parts, [val], out, title="again", results=list(files.values()))
    assert (out / "report.pdf").read_bytes() == before


def test_a_summary_longer_than_a_page_goes_on_over_more_pages():
    """A summary whose lines do not fit one A4 page at 8 pt (many studies, long answers) goes on
    over more A4 pages (every line once, inside its page), and its PNG is one tall figure; a short
    one stays one page at the largest font."""
    from clutchlab.report.common import summary_layout, texts_outside, title_page

    def summary(k, answers):
        return {
            "name": f"s{k}",
            "title": f"Study 's{k}': a study",
            "run": "10 scenarios, design factorial over x (10)",
            "model": "a model",
            "status": "status: ok 10",
            "answers": [f"answer {i}: " + "sheet_thickness = 2.4 mm, " * 7 for i in range(answers)],
        }

    short = [summary(0, 2)]
    size, _, pages = summary_layout("T", short, [])
    assert size == 9.5 and len(pages) == 1
    long = [summary(k, 12) for k in range(4)]
    links = {"s0": "s0_explorer.html"}
    size, _, pages = summary_layout("T", long, [], explorers=links)
    assert size == 8.0 and len(pages) >= 2
    drawn = [line for page in pages for block in page for line in block]
    assert sum(line.startswith("answer ") for line in drawn) == 4 * 12
    assert drawn.count("interactive explorer (open in a browser): s0_explorer.html") == 1
    for k in range(len(pages)):
        fig = title_page("T", "v", long, [], explorers=links, page=k)
        assert tuple(fig.get_size_inches()) == (11.69, 8.27) and not texts_outside(fig), k
    tall = title_page("T", "v", long, [], explorers=links)
    assert tall.get_size_inches()[1] > 8.27 and not texts_outside(tall)
    assert {t.get_text() for t in tall.texts} >= set(drawn)


def _variants():
    """Each study of config/config.yaml with no factor, and with each of its first three factors
    alone (the others fixed at their seed values)."""
    from pathlib import Path

    import yaml

    full = yaml.safe_load(
        (Path(__file__).resolve().parents[1] / "config" / "config.yaml").read_text()
    )
    from conftest import without_robust

    for name in full["studies"]:
        sec = without_robust(full[name])  # (robust pages: tests/test_robust.py)
        params = sec.get("parameters") or {}
        factors = [k for k, v in params.items() if isinstance(v, dict)]
        # (a sampled design needs a factor to sample)
        for keep in ([[]] if sec["design"] == "factorial" else []) + [[f] for f in factors[:3]]:
            new = {k: v for k, v in params.items() if not isinstance(v, dict)}
            for k in keep:
                v = params[k]
                new[k] = (
                    {"values": v["values"][:3]}
                    if "values" in v
                    else {**v, "num": 3}
                    if sec["design"] == "factorial"
                    else v
                )
            body = {k: v for k, v in sec.items() if k not in ("parameters", "chunks")}
            if sec["design"] != "factorial":
                body["samples"] = 4
            yield pytest.param(
                name, {**body, "parameters": new}, id=f"{name}-{'-'.join(keep) or 'none'}"
            )


@pytest.mark.parametrize("name, section", list(_variants()))
def test_pages_draw_with_any_factor_fixed(name, section):
    """A factor fixed to one value is a 0-d input, not a dimension: every page still draws (the
    diaphragm reserve map used to crash on a fixed cone-height ratio)."""
    import matplotlib.pyplot as plt

    ds = pipeline.run_study(resolve({"studies": [name], name: section})[name])
    pages = report.study_pages(name, ds)
    assert [s for s, _ in pages] == list(report.study_page_stems(name))
    for _, fig in pages:
        fig.canvas.draw()
        plt.close(fig)


def test_front_table_lists_front_designs_spread_along_it():
    """<study>_pareto.csv: at most 15 designs, all of rank 0, ordered along the first objective,
    both ends of the front included, factor values in the units engineers read (the header names
    each unit: the pressure angle in deg, the release time in ms), then the constraints' outputs
    and margins."""
    import numpy as np

    from clutchlab.report import answers

    sec = resolve(
        {
            "studies": ["centrifugal"],
            "centrifugal": {
                "design": "factorial",
                "parameters": {
                    "pressure_angle": {"min": "20 deg", "max": "60 deg", "num": 25},
                    "friction_coefficient": {"min": 0.25, "max": 0.6, "num": 25},
                },
            },
        }
    )["centrifugal"]
    ds = pipeline.run_study(sec)
    header, rows = answers.front_rows(ds)
    assert (
        header[:4]
        == [
            "friction_coefficient [-]",
            "pressure_angle [deg]",
            "reserve_factor [-]",
            "release_time [ms]",
        ]
        and len(rows) <= answers.MAX_ROWS
    )
    # (release_margin min 0 is its own constraint margin: written once)
    assert header[4:] == ["release_margin [-]", "reserve_factor_constraint_margin [-]"]
    front = ds.where(ds["pareto_rank"] == 0)
    obj = [o.split(":")[0] for o in sec["objectives"]]
    first = np.sort(front[obj[0]].values[np.isfinite(front[obj[0]].values)])
    got = [r[2] for r in rows]
    assert got == sorted(got) and got[0] == first[0] and got[-1] == first[-1]
    for r in rows:
        pick = ds.sel(friction_coefficient=r[0], pressure_angle=np.deg2rad(r[1]), method="nearest")
        assert np.rad2deg(float(pick["pressure_angle"])) == pytest.approx(r[1], rel=1e-12)
        assert int(pick["pareto_rank"]) == 0
        assert float(pick[obj[1]]) * 1e3 == pytest.approx(r[3], rel=1e-12)
        assert float(pick["release_margin"]) == pytest.approx(r[4], rel=1e-12)
        margins = pick["constraint_margin"].sel(constraint=["reserve_factor", "release_margin"])
        assert [float(margins.values[0])] == r[5:] and margins.values[1] == r[4]


@pytest.mark.parametrize(
    "objectives, panels",
    [
        (["reserve_factor:max", "release_time:min"], 1),
        (["reserve_factor:max", "release_time:min", "engagement_speed:min"], 3),
        (
            [
                "reserve_factor:max",
                "release_time:min",
                "engagement_speed:min",
                "release_margin:max",
            ],
            6,
        ),
    ],
)
def test_answers_page_projects_three_or_more_objectives(objectives, panels):
    """Issue 15 item 5: for 3+ objectives the answers page draws every pair of objectives (front
    designs marked), each axis labelled with its objective and sense, and its table lists them all."""
    from clutchlab.report import answers

    sec = resolve(
        {
            "studies": ["centrifugal"],
            "centrifugal": {
                "design": "factorial",
                "objectives": objectives,
                "parameters": {
                    "pressure_angle": {"min": "20 deg", "max": "60 deg", "num": 6},
                    "friction_coefficient": {"min": 0.25, "max": 0.6, "num": 5},
                },
            },
        }
    )["centrifugal"]
    fig = answers.page("centrifugal", pipeline.run_study(sec))
    fig.canvas.draw()
    labelled = [ax for ax in fig.axes if ax.get_xlabel().endswith(("(minimised)", "(maximised)"))]
    assert len(labelled) == panels
    pairs = {(ax.get_xlabel().split(" [")[0], ax.get_ylabel().split(" [")[0]) for ax in labelled}
    names = [o.split(":")[0] for o in objectives]
    assert len(pairs) == panels and all(a in names and b in names for a, b in pairs)
    header, _ = answers.front_rows(pipeline.run_study(sec))
    assert all(any(h.startswith(n + " [") for h in header) for n in names)
    import matplotlib.pyplot as plt

    plt.close(fig)


def _sampled_section(name):
    """The default config's section of a study as a Sobol sample over its factors' ranges."""
    import yaml

    from clutchlab import studies
    from conftest import without_robust

    raw = without_robust(yaml.safe_load((ROOT / "config" / "config.yaml").read_text())[name])
    params = {}
    for key, spec in raw["parameters"].items():
        if isinstance(spec, dict) and not studies.get(name).parameter(key).integer:
            vals = spec.get("values") or [spec["min"], spec["max"]]
            spec = {"min": vals[0], "max": vals[-1]}
        params[key] = spec
    return {**raw, "design": "sobol", "samples": 128, "seed": 1, "parameters": params}


@pytest.mark.parametrize(
    "name", ["diaphragm_spring", "engagement", "centrifugal", "sprag", "roller"]
)
def test_every_page_draws_a_sampled_design(name):
    """Issue 16 item 4: every figure of every study works for a sampled design (the 2^20 run's sprag
    pass map and the roller pages printed 'needs a factorial design' instead)."""
    import matplotlib.pyplot as plt

    from clutchlab.report import answers

    ds = pipeline.run_study(resolve({"studies": [name], name: _sampled_section(name)})[name])
    for stem, fig in report.study_pages(name, ds) + [("answers", answers.page(name, ds))]:
        fig.canvas.draw()
        texts = [t.get_text() for t in fig.texts] + [
            t.get_text() for ax in fig.axes for t in ax.texts
        ]
        assert not [t for t in texts if "needs a" in t or "not a dimension" in t], (stem, texts)
        assert any(ax.collections or ax.lines or ax.images for ax in fig.axes), stem
        plt.close(fig)


def test_sampled_maps_bin_many_designs():
    """Above SCATTER_MAX designs a sampled category map is an image of the share passing per bin
    (small and fast at 10^6 designs), below it one marker per design."""
    import matplotlib.pyplot as plt
    from matplotlib.collections import PathCollection, QuadMesh

    from clutchlab.report.common import SCATTER_MAX, sampled_category_map

    rng = np.random.default_rng(0)
    cats = (("ok", "g"), ("bad", "r"))
    for n, kind in ((SCATTER_MAX, PathCollection), (10 * SCATTER_MAX, QuadMesh)):
        x, y = rng.random(n), rng.random(n)
        fig, ax = plt.subplots()
        sampled_category_map(ax, x, y, (x + y > 1).astype(int), cats)
        assert [type(c) for c in ax.collections] == [kind]
        if kind is QuadMesh:  # the share passing: 1 where x + y < 1 everywhere in the bin
            share = ax.collections[0].get_array().reshape(30, 30)
            assert share[0, 0] == 1.0 and share[-1, -1] == 0.0
        plt.close(fig)


def test_a_binned_value_maps_colour_bar_label_stays_on_the_page():
    """The heat page's panel of 900 000 designs: the binned map's colour bar names what it
    shows and its count on two lines, inside the page (on one line it ran off the page)."""
    import matplotlib.pyplot as plt

    from clutchlab.report.common import (
        A4_LANDSCAPE,
        SCATTER_MAX,
        sampled_value_map,
        texts_outside,
    )

    rng = np.random.default_rng(0)
    n = 200 * SCATTER_MAX
    fig, axes = plt.subplots(  # (the heat page's layout)
        2, 2, figsize=A4_LANDSCAPE, gridspec_kw={"hspace": 0.45, "wspace": 0.5, "top": 0.85}
    )
    x, y = rng.random(n), rng.random(n)
    sampled_value_map(axes[1, 0], x, y, 340 + 30 * x, "peak face temperature [°C]")
    fig.canvas.draw()
    assert not texts_outside(fig), texts_outside(fig)
    assert any(f"(median per bin, {n} designs)" in t.get_text() for t in fig.findobj(plt.Text))
    plt.close(fig)


@pytest.mark.parametrize("statistic", ["mean", "median"])
def test_binned_statistic_as_scipy(statistic):
    """The maps' per-bin mean and median equal scipy.stats.binned_statistic_2d's (equal bins over
    the range and a discrete factor's midpoints; empty bins NaN; a value on the last edge in the
    last bin; points outside given edges left out)."""
    from scipy.stats import binned_statistic_2d

    from clutchlab.report.common import _edges, binned_2d

    rng = np.random.default_rng(2)
    x = rng.uniform(0.0, 3.0, 5000)
    x[:2] = 0.0, 3.0  # the range's ends
    y = rng.integers(0, 4, x.size).astype(float)
    z = rng.normal(size=x.size)
    for xe, ye in ((_edges(x, 30), _edges(y, 30)), (np.linspace(0.5, 2.5, 7), _edges(y, 30))):
        want = binned_statistic_2d(x, y, z, statistic, bins=[xe, ye]).statistic
        got = binned_2d(x, y, z, xe, ye, statistic)
        np.testing.assert_allclose(got, want, rtol=1e-13, atol=0.0)
    assert np.isnan(binned_2d(x, y, z, np.linspace(5, 6, 3), _edges(y, 30), statistic)).all()
    with pytest.raises(ValueError, match="statistic"):
        binned_2d(x, y, z, xe, ye, "max")


def test_a_fitted_table_is_as_tall_as_its_rows_and_stays_in_its_axes():
    """The answers and robust pages' tables: one row is not stretched over the axes (it takes
    its header and one row of text from the top), fifteen rows (the answers page's most) keep
    every text, column names wrapped to their column, inside its cell, and forty rows still stay
    inside the axes (thinner rows)."""
    import matplotlib.pyplot as plt

    from clutchlab.report.common import A4_LANDSCAPE, fitted_table, texts_outside_cells

    header = ["sheet_thickness [mm]", "friction_coefficient [-]", "quantile_peak_jerk [rad/s^3]"]
    for n in (1, 15, 40):
        fig = plt.figure(figsize=A4_LANDSCAPE)
        ax = fig.add_axes([0.1, 0.05, 0.3, 0.4])
        ax.set_axis_off()
        table = fitted_table(ax, header, [["2.6", "0.4", "9.116e+06"]] * n)
        fig.canvas.draw()
        cells = table.get_celld()
        top = max(c.get_window_extent().y1 for c in cells.values())
        bottom = min(c.get_window_extent().y0 for c in cells.values())
        box = ax.get_window_extent()
        assert top <= box.y1 + 1 and bottom >= box.y0 - 1, n
        row_in = cells[1, 0].get_window_extent().height / fig.dpi
        assert row_in <= 1.6 * 1.2 * 8 / 72 + 1e-6, n
        if n == 1:  # the header and one row: well under a third of the axes
            assert top - bottom < 0.3 * box.height
        if n <= 15:
            assert not texts_outside_cells(fig), texts_outside_cells(fig)
        plt.close(fig)


def test_studies_never_import_the_report():
    """DESIGN.md: studies compute, the report draws and looks a study's pages up by its name; a
    study job (all of clutchlab.studies loaded) imports neither the report nor matplotlib, and
    every registered study has its pages."""
    import ast
    import subprocess
    import sys
    from pathlib import Path

    import clutchlab.studies

    for path in Path(clutchlab.studies.__file__).parent.glob(
        "*.py"
    ):  # also imports inside functions
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, (ast.Import, ast.ImportFrom)):
                names = [getattr(node, "module", None) or ""] + [a.name for a in node.names]
                assert not any("report" in n or "matplotlib" in n for n in names), (
                    path.name,
                    names,
                )
    code = (
        "import sys; from clutchlab import studies; studies._load_all(); "
        "print(sorted(studies.REGISTRY), 'clutchlab.report' in sys.modules, 'matplotlib' in sys.modules)"
    )
    out = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, check=True
    ).stdout.split()
    assert out[-2:] == ["False", "False"], out
    from clutchlab import studies

    studies._load_all()
    assert sorted(report.FIGURE_MODULES) == sorted(studies.REGISTRY)
    for name in studies.REGISTRY:
        assert report.study_page_stems(name)


def _single_factors():
    """Every parameter of every study varied alone over two values near its seed value (a count
    by 2, a choice over both, an infinite default over finite values), the rest at the seed."""
    from clutchlab import studies

    for name in ("diaphragm_spring", "engagement", "centrifugal", "sprag", "roller"):
        for p in studies.get(name).parameters:
            d = p.default
            if p.choices is not None:
                vals = list(p.choices)
            elif not np.isfinite(d):
                vals = [50.0, 100.0] if p.units == "rad/s" else [1.0, 2.0]
            elif p.integer:
                vals = [d, d + 2]
            elif d == 0:
                vals = [0.0, 1e-3 if p.units in ("m", "kg") else 0.01]
            else:
                vals = [d, d * 1.05]
            if p.units == "K":
                vals = [f"{v} K" for v in vals]
            # one parameter per study in the quick suite (the diaphragm's friction coefficient
            # crashed its pages), every one in the slow suite
            quick = p.name in QUICK_SINGLE_FACTORS.get(name, ())
            yield pytest.param(
                name, p.name, vals, id=f"{name}-{p.name}", marks=() if quick else pytest.mark.slow
            )


QUICK_SINGLE_FACTORS = {
    "diaphragm_spring": ("friction_coefficient",),
    "engagement": ("ambient_temperature",),
    "centrifugal": ("idle_speed",),
    "sprag": ("rise_time",),
    "roller": ("control_stop_time",),
}


@pytest.mark.parametrize("name, factor, values", list(_single_factors()))
def test_pages_draw_with_any_single_factor_varied(name, factor, values):
    """A factorial grid over any one parameter (the report's figures expect the default config's
    factors) reaches every page of its study: its own, the answers and the sensitivity page."""
    import matplotlib.pyplot as plt

    from clutchlab import explore
    from clutchlab.report import answers

    sec = resolve(
        {
            "studies": [name],
            name: {"design": "factorial", "parameters": {factor: {"values": values}}},
        }
    )[name]
    ds = pipeline.run_study(sec)
    assert ds[factor].size == len(values)
    outputs = [o.split(":")[0] for o in sec["objectives"]] + list(sec["constraints"])
    figs = [fig for _, fig in report.study_pages(name, ds)]
    figs += [
        answers.page(name, ds),
        answers.sensitivity_page(name, explore.sensitivity(ds, outputs)),
    ]
    for fig in figs:
        fig.canvas.draw()
        plt.close(fig)


@pytest.mark.parametrize(
    "name",
    [
        "diaphragm_spring",
        *(
            pytest.param(n, marks=pytest.mark.slow)
            for n in ("engagement", "centrifugal", "sprag", "roller")
        ),
    ],
)
def test_a_grid_of_no_factor_runs_in_chunks_to_its_report(tmp_path, name):
    """A factorial section with no factor is a one-scenario study: its chunks (all but one empty)
    merge and its report builds (no sensitivity page: nothing varies)."""
    from clutchlab import doe, traces

    sec = resolve({"studies": [name], "chunks": 3, name: {"design": "factorial"}})[name]
    design = store.write(doe.build_design(sec), tmp_path / f"{name}_design.h5")
    design = store.load(design)
    chunks = []
    for i in range(sec["chunks"]):
        chunks.append(tmp_path / f"{name}_{i}.h5")
        store.write(
            pipeline.run_chunk(design, sec["options"], 3, i), chunks[-1], with_checksum=True
        )
    out = tmp_path / f"{name}.h5"
    pipeline.merge_to_file(design, chunks, out, sec["objectives"], sec["constraints"])
    merged = store.load(out)
    single = pipeline.run_study(sec)
    assert merged["status"].size == 1 and int(merged["status"].values.ravel()[0]) == int(
        single["status"]
    )
    traced = store.write(  # the workflow's traces job: the design the pages show
        traces.compute(merged, sec["options"]), tmp_path / f"{name}_traces.h5"
    )
    written = report.build(
        {name: out}, [], tmp_path / f"report_{name}", traces_files={name: traced}
    )
    assert (tmp_path / f"report_{name}" / "report.pdf").stat().st_size > 0 and written


def test_point_labels_never_overprint_each_other():
    """The work-precision pages label each tolerance beside its point; where points crowd (two
    tolerances at one error and nearly one time), a label moves to a free side or is left out
    rather than printed over another one, and one on a free point stays up and right of it."""
    import matplotlib.pyplot as plt

    from clutchlab.report.common import A4_LANDSCAPE, label_points, texts_overprinted

    fig, ax = plt.subplots(figsize=A4_LANDSCAPE)
    x = [2.2e-3, 2.9e-3, 3.9e-3, 4.0e-3, 4.05e-3, 1e-5]
    y = [6e-3, 4.6e-3, 4.6e-3, 4.6e-3, 4.6e-3, 1e-8]
    ax.loglog(x, y, "o")
    label_points(
        ax, [(a, b, f"rtol 1e-{2 * i + 4:02d}") for i, (a, b) in enumerate(zip(x, y, strict=True))]
    )
    fig.canvas.draw()
    assert not texts_overprinted(fig), texts_overprinted(fig)
    texts = {t.get_text(): t for t in ax.texts}
    assert 4 <= len(texts) < 6 and "rtol 1e-14" in texts  # the free point's label kept
    assert texts["rtol 1e-14"].get_position() == (4, 4)
    plt.close(fig)


def test_many_fronts_share_one_colour_after_the_eight_named():
    """A front per operating condition: the first eight are named in the legend, each in a colour
    of its own (not the feasible designs' blue); the others are drawn in one colour of their
    own, named once ("... N more"), never in a colour that names another front."""
    import matplotlib.colors as mcolors
    import matplotlib.pyplot as plt

    from clutchlab.report import answers

    sec = resolve(
        {
            "studies": ["sprag"],
            "sprag": {
                "design": "factorial",
                "parameters": {
                    "torque": {"min": "100 N*m", "max": "1000 N*m", "num": 12},
                    "sprags": {"values": [14, 16, 18, 20, 22]},
                    "sprag_length": {"values": ["12 mm", "16.891 mm", "22 mm"]},
                },
            },
        }
    )["sprag"]
    fig = answers.page("sprag", pipeline.run_study(sec))
    fronts = [ln for ax in fig.axes for ln in ax.get_lines() if ln.get_marker() == "o"]
    named = [ln for ln in fronts if not ln.get_label().startswith("_")]
    assert len(fronts) == 12 and len(named) == 9 and named[-1].get_label() == "... 4 more"
    colours = [mcolors.to_hex(ln.get_color()) for ln in fronts]
    assert len(set(colours[:8])) == 8 and mcolors.to_hex("tab:blue") not in colours
    assert set(colours[8:]) == {colours[8]} and colours[8] not in colours[:8]
    plt.close(fig)


def test_the_tradeoff_page_draws_a_colour_per_operating_condition_over_its_noise_draws():
    """A robust engagement study ranks a front per operating condition and noise draw: the
    trade-off page draws every draw's front in its condition's colour and names each condition
    once, in the units engineers read, with its number of draws (it used to name eight draws
    of the first condition and cycle ten colours over all the others)."""
    import matplotlib.colors as mcolors
    import matplotlib.pyplot as plt

    from clutchlab.report import engagement_figures

    sec = resolve(
        {
            "studies": ["engagement"],
            "engagement": {
                "design": "factorial",
                "robust": True,
                "noise_samples": 2,
                "parameters": {
                    "ramp_time": {"values": ["0.1 s", "0.2 s", "0.3 s"]},
                    "friction_coefficient": {"values": [0.35, 0.4]},
                    "driven_inertia": {"values": ["0.021 kg*m^2", "0.05 kg*m^2"]},
                },
            },
        }
    )["engagement"]
    ds = pipeline.run_study(sec)
    fig = engagement_figures.tradeoff(ds)
    lines = [ln for ln in fig.axes[0].get_lines() if ln.get_linestyle() == "-"]
    named = [ln.get_label() for ln in lines if not ln.get_label().startswith("_")]
    draws = ds.sizes["noise"]
    assert named == [
        f"Pareto front at driven_inertia {j} kg·m² ({draws} noise draws)" for j in ("0.021", "0.05")
    ]
    colours = {mcolors.to_hex(ln.get_color()) for ln in lines}
    assert len(lines) == 2 * draws and len(colours) == 2
    plt.close(fig)


def test_the_maps_page_shows_no_slip_work_where_an_engagement_never_locks():
    """A design that never locks has its window's slip work, not an engagement's: the slip-work
    map leaves it blank, as the lock-up map does (it used to colour it, and set the colour
    scale's top with it); the clamp force is in kN."""
    import matplotlib.pyplot as plt

    from clutchlab.report import engagement_figures

    sec = resolve(
        {
            "studies": ["engagement"],
            "engagement": {
                "design": "factorial",
                "parameters": {
                    "sheet_thickness": {"values": ["2.0 mm", "2.3 mm", "2.6 mm"]},
                    "ramp_time": {"values": ["0.1 s", "0.3 s"]},
                    "load_torque": "120 N*m",
                },
            },
        }
    )["engagement"]
    ds = pipeline.run_study(sec)
    never = ~np.isfinite(ds["lockup_time"].values)
    assert never.any() and np.isfinite(ds["slip_work"].values[never]).all()
    fig = engagement_figures.maps(ds)
    slip, lock = (np.ma.getmaskarray(ax.collections[0].get_array()) for ax in fig.axes[:2])
    assert slip.any() and (slip == lock).all()
    assert fig.axes[0].get_ylabel() == "clamp force from the spring design [kN]"
    plt.close(fig)


def test_an_axis_multiplier_goes_into_its_label():
    """matplotlib prints a large axis' power of ten as a bare "1e6" at its end; it goes into the
    axis label (before the unit, or as the unit of a dimensionless or unlabelled one) and the
    ticks read 1-8. A small axis, an additive offset and an unlabelled axis are left alone."""
    import matplotlib.pyplot as plt

    from clutchlab.report.common import fold_multipliers

    fig, axes = plt.subplots(1, 4)
    labels = ("peak_jerk [rad/s³] (minimised)", "ratio [-]", "count", "")
    for ax, label in zip(axes, labels, strict=True):
        ax.plot([0, 1], [1e6, 8e6])
        ax.set_ylabel(label)
        ax.set_xlabel("time [ms]")
    axes[2].plot([0, 1], [1e-7, 3e-6])  # (now 0 to 8e6: still a multiplier)
    fold_multipliers(fig)
    fig.canvas.draw()
    assert [ax.get_ylabel() for ax in axes] == [
        "peak_jerk [10⁶ rad/s³] (minimised)",
        "ratio [10⁶]",
        "count [10⁶]",
        "",  # (no label to carry it: matplotlib's multiplier kept)
    ]
    assert all(ax.get_xlabel() == "time [ms]" for ax in axes)  # (0 to 1: none)
    ticks = [t.get_text() for t in axes[0].get_yticklabels() if t.get_text()]
    assert "8" in ticks and not axes[0].yaxis.get_offset_text().get_text()
    assert axes[3].yaxis.get_offset_text().get_text()
    fig2, ax = plt.subplots()
    ax.plot([0, 1], [1000.001, 1000.002])  # an additive offset: kept as matplotlib writes it
    ax.set_ylabel("speed [rpm]")
    fold_multipliers(fig2)
    assert ax.get_ylabel() == "speed [rpm]"
    plt.close(fig)
    plt.close(fig2)


def test_an_answers_page_without_a_feasible_design_lists_the_nearest():
    """Where no design meets every limit, the answers page's lower half was blank; it lists the
    designs nearest to feasible (status ok first, then the largest least margin) with their
    status and every constraint's margin, and its title says so."""
    import matplotlib.pyplot as plt

    from clutchlab.explore import flat
    from clutchlab.report import answers
    from clutchlab.report.common import texts_outside_cells

    sec = resolve(
        {
            "studies": ["diaphragm_spring"],
            "diaphragm_spring": {
                "design": "factorial",
                "parameters": {
                    "sheet_thickness": {"min": "2.25 mm", "max": "2.4 mm", "num": 4},
                    "cone_height_ratio": {"values": [1.45, 1.5, 1.55]},
                },
                "constraints": {"reserve_factor": {"min": 1.6}},
            },
        }
    )["diaphragm_spring"]
    ds = pipeline.run_study(sec)
    assert not ds["feasible"].any()
    order = answers.nearest_order(ds)
    least = ds["constraint_margin"].min("constraint").values.reshape(-1)[order]
    assert order.size == 12 and list(least) == sorted(least, reverse=True)
    assert np.all(flat(ds, "status")[order] == 0)
    fig = answers.page("diaphragm_spring", ds)
    assert "table: the " in fig._suptitle.get_text().replace("\n", " ")
    table = next(a for a in fig.axes if a.tables).tables[0]
    cells = table.get_celld()
    rows = 1 + max(r for r, _ in cells)
    first = [cells[r, 0].get_text().get_text() for r in range(1, rows)]
    assert [f.removeprefix("★ ") for f in first] == ["ok"] * (rows - 1) and rows - 1 >= 5
    # the design the pages show (no feasible one: the one nearest the ideal point) starred
    shown, _ = traces.shown_design(ds)
    starred = [int(order[r]) for r, f in enumerate(first) if f.startswith("★ ")]
    assert starred == ([shown] if shown in order[: rows - 1] else [])
    head = [
        cells[0, c].get_text().get_text().replace("\n", "")
        for c in range(1 + max(c for _, c in cells))
    ]
    assert head[-1].startswith("reserve_") and "margin" in head[-1]
    best = float(cells[1, len(head) - 1].get_text().get_text())
    assert best == pytest.approx(float(least[0]), rel=1e-3)
    assert not texts_outside_cells(fig), texts_outside_cells(fig)
    plt.close(fig)


def test_the_roller_overstress_note_counts_every_design_far_above_the_allowable():
    """The roller pages' note counted only the designs whose status is dynamic_overstress; a
    design whose static stress fails too has status above_allowable and the highest dynamic
    stresses, and was left out of the count and the range."""
    import xarray as xr

    from clutchlab import status as st
    from clutchlab.report.roller_figures import DYNAMIC_STRESS_FACTOR, overstress_note

    f = DYNAMIC_STRESS_FACTOR
    codes = [st.CODE["dynamic_overstress"], st.CODE["above_allowable"], st.CODE["ok"], 0]
    ds = xr.Dataset(
        {
            "status": ("run", np.array(codes, dtype=st.DTYPE)),
            "peak_contact_stress": ("run", np.array([1.2 * f, 2.5 * f, 0.5, np.nan]) * 3e9),
            "contact_allowable": ("run", np.full(4, 3e9)),
        }
    )
    note = overstress_note(ds)
    assert note.startswith(
        f"2 of 4 designs: peak dynamic contact stress {1.2 * f:.1f}-{2.5 * f:.1f}"
    )
    assert "1 with status dynamic_overstress, the other 1 fail first as above_allowable" in note
    assert overstress_note(ds.isel(run=[2, 3])) == ""


def test_an_objectives_constraint_limit_is_drawn_where_it_falls_in_the_panel():
    """The answers page draws a constrained objective's limit as a dashed line (how far the
    designs are from feasible, where none is) when it falls inside the panel, in display units,
    and leaves the panel's range as it was."""
    import matplotlib.pyplot as plt
    import xarray as xr

    from clutchlab.report.answers import _limit_lines

    ds = xr.Dataset(
        {"engagement_time": ("run", [1e-4], {"units": "s"}), "y": ("run", [1.0], {"units": "1"})},
        coords={
            "constraint": (
                "constraint",
                ["engagement_time"],
                {"limits": "engagement_time:max:0.0005"},
            )
        },
    )
    fig, ax = plt.subplots()
    for view, drawn in (((0.0, 1.0), True), ((0.6, 1.0), False)):
        ax.cla()
        ax.set_xlim(*view)
        _limit_lines(ax, ds, "engagement_time", "y")
        lines = [ln for ln in ax.get_lines() if ln.get_label() == "constraint limit"]
        assert len(lines) == drawn and ax.get_xlim() == view
        if drawn:
            assert lines[0].get_xdata()[0] == pytest.approx(0.5)  # (ms)
    plt.close(fig)


def _engagement_grid(constraints=None, **values) -> dict:
    """A small factorial engagement study over the given factors' values (and constraints)."""
    body = {
        "design": "factorial",
        "parameters": {k: {"values": v} for k, v in values.items()},
    }
    if constraints:
        body["constraints"] = constraints
    return resolve({"studies": ["engagement"], "engagement": body})["engagement"]


def test_the_tradeoff_page_greys_the_scenarios_a_constraint_fails():
    """The trade-off page coloured every scenario whose status is ok by its lock-up time, those
    over the lock-up limit too (they read as answers); those a constraint fails are grey."""
    import matplotlib.pyplot as plt

    from clutchlab.explore import flat
    from clutchlab.report import engagement_figures

    sec = _engagement_grid(
        {"lockup_time": {"max": "250 ms"}},
        ramp_time=["0.1 s", "0.2 s", "0.3 s"],
        friction_coefficient=[0.35, 0.4],
        driven_inertia=["0.021 kg*m^2", "0.05 kg*m^2"],
    )
    ds = pipeline.run_study(sec)
    ok = (flat(ds, "status") == 0) & np.isfinite(flat(ds, "peak_jerk"))
    failing = ok & ~flat(ds, "feasible").astype(bool)
    assert failing.any() and (ok & ~failing).any()
    fig = engagement_figures.tradeoff(ds)
    grey = [c for c in fig.axes[0].collections if c.get_label().startswith("a constraint fails")]
    assert len(grey) == 1 and len(grey[0].get_offsets()) == failing.sum()
    coloured = [c for c in fig.axes[0].collections if c.get_array() is not None]
    assert len(coloured[0].get_offsets()) == (ok & ~failing).sum()
    plt.close(fig)


def test_a_title_wraps_into_lines_of_even_length():
    """A title's last word hung alone on its line ("-20.0 %"); wrapped into the same number of
    lines, evenly."""
    from clutchlab.report.common import wrap_even

    text = (
        "Traces of the run's best robust design at its binding condition: "
        + "x = 1.0 mm, " * 5
        + "-20.0 %"
    )
    lines = wrap_even(text, 100)
    assert len(lines) == 2 and " ".join(lines) == text
    assert max(map(len, lines)) - min(map(len, lines)) <= 12 and lines[-1] != "-20.0 %"
    assert wrap_even("short", 100) == ["short"]


def test_the_maps_page_marks_the_cells_over_a_constraint_limit():
    """The lock-up map coloured the cells over the study's lock-up limit like the others; they
    are framed and hatched, named in a legend under the map (on it, it hid a cell)."""
    import matplotlib.pyplot as plt
    from matplotlib.patches import Rectangle

    from clutchlab.report import engagement_figures

    sec = _engagement_grid(
        {"lockup_time": {"max": "250 ms"}},
        sheet_thickness=["2.2 mm", "2.45 mm"],
        ramp_time=["0.1 s", "0.2 s", "0.3 s"],
    )
    ds = pipeline.run_study(sec)
    over = int((ds["lockup_time"] > 0.25).sum())
    assert 0 < over < ds["lockup_time"].size
    fig = engagement_figures.maps(ds)
    framed = [
        p for p in fig.axes[1].patches if isinstance(p, Rectangle) and p.get_edgecolor()[0] > 0.5
    ]
    assert len(framed) == 2 * over  # (a hatch and a frame a cell)
    legend = fig.axes[1].get_legend()
    assert "lockup_time max: 250 ms fails" in [t.get_text() for t in legend.get_texts()]
    assert not fig.axes[0].patches  # (no constraint on the slip work)
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    assert not legend.get_window_extent(renderer).overlaps(fig.axes[1].get_window_extent(renderer))
    plt.close(fig)


def test_the_heat_pages_two_temperature_maps_share_their_colours():
    """(c) the hottest design per grid point and (d) every design were coloured on scales of
    their own (the same colour read 90 °C on one and 80 °C on the other); one scale."""
    import matplotlib.pyplot as plt

    from clutchlab.report import engagement_figures

    sec = _engagement_grid(
        sheet_thickness=["2.2 mm", "2.45 mm"],
        ramp_time=["0.1 s", "0.2 s", "0.3 s"],
        friction_coefficient=[0.35, 0.4],
    )
    fig = engagement_figures.heat_page(pipeline.run_study(sec))
    mappables = [
        c for ax in fig.axes for c in ax.collections if c.get_array() is not None and ax.get_title()
    ]
    assert len(mappables) == 2 and mappables[0].get_clim() == mappables[1].get_clim()
    plt.close(fig)
