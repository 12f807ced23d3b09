"""The report's numerics section (issue 17 item 1): small solver benchmarks run in the study run,
one work-precision page per solver with the ratio at equal error."""

import matplotlib

matplotlib.use("Agg")

from clutchlab.bench import numerics  # noqa: E402


def test_files_and_stems_follow_the_studies():
    assert numerics.files(["diaphragm_spring", "sprag", "roller"]) == [
        "sprag_benchmark.csv",
        "roller_benchmark.csv",
    ]
    assert numerics.stems(["diaphragm_spring", "engagement"]) == ["numerics_engagement"]


def test_ratio_at_equal_error():
    rows = [
        dict(method="clutchlab a", seconds_per_scenario=1e-5, err=1e-9),
        dict(method="clutchlab a", seconds_per_scenario=2e-5, err=1e-11),
        dict(method="scipy x", seconds_per_scenario=1e-3, err=1e-10),
        dict(method="scipy x", seconds_per_scenario=1e-2, err=1e-13),
    ]  # clutchlab never that accurate
    out = numerics._ratios(rows, "err", "clutchlab")
    assert len(out) == 1 and out[0][1]["err"] == 1e-11 and out[0][2] == 50.0


def test_small_runs_draw_their_pages(tmp_path):
    written = numerics.run(tmp_path, ["sprag", "roller", "diaphragm_spring", "centrifugal"])
    assert [p.name for p in written] == [
        "sprag_benchmark.csv",
        "roller_benchmark.csv",
        "centrifugal_benchmark.csv",
    ]
    pages = dict(numerics.pages(tmp_path))
    assert set(pages) == {"numerics_sprag", "numerics_roller", "numerics_centrifugal"}
    # a run of other studies into the same folder draws its own studies' pages only, in its order
    assert [stem for stem, _ in numerics.pages(tmp_path, ["roller", "engagement", "sprag"])] == [
        "numerics_roller",
        "numerics_sprag",
    ]
    for fig in pages.values():
        text = " ".join(t.get_text() for t in fig.texts)
        assert "x faster" in text  # the ratio at equal error, measured in this run
    release = numerics._read(tmp_path / "centrifugal_benchmark.csv")
    assert (
        release[0]["max_release_time_error_s"] < 1e-10
    )  # the closed form against DOP853 at rtol 1e-13
    roller = numerics._read(tmp_path / "roller_benchmark.csv")
    assert {"scipy solve_ivp LSODA per scenario", "scipy solve_ivp Radau per scenario"} <= {
        r["method"] for r in roller
    }


def test_the_engagement_numerics_time_only_the_study_friction_laws(tmp_path, monkeypatch):
    """The default study (constant μ) times its own solver only, so that its run compiles none of
    the integrators the other friction laws need; the page draws one panel a law."""
    from clutchlab import config
    from clutchlab.studies.engagement import friction_laws

    def laws(**params):
        sec = {"design": "factorial", "parameters": params}
        return friction_laws(
            config.resolve({"studies": ["engagement"], "engagement": sec})["engagement"]
        )

    assert laws() == ["constant_mu"]
    assert laws(stribeck_speed={"values": ["inf", "30 rad/s"]}) == ["constant_mu", "stribeck"]
    assert laws(fade_coefficient={"values": [0.0, "0.01 1/K"]}) == ["constant_mu", "fade"]
    monkeypatch.setitem(numerics.SIZES, "engagement", dict(n=20, n_ref=2))
    numerics.run(tmp_path, ["engagement"], friction_laws=laws())
    rows = numerics._read(tmp_path / "compliant_benchmark.csv")
    assert {r["variant"] for r in rows} == {"constant_mu"}
    ((stem, fig),) = numerics.pages(tmp_path)
    assert stem == "numerics_engagement"
    assert [ax.get_title().split("\n")[0] for ax in fig.axes if ax.get_visible()] == [
        "constant μ (default study)"
    ]
