"""Robust studies: crossed designs (design × conditions × noise) and their robust answers."""

import itertools

import numpy as np
import pytest
import xarray as xr

from clutchlab import doe, explore, pipeline, store, studies
from clutchlab import robust as rb
from clutchlab.config import resolve

NOMINAL_MU = 0.35
SCATTER = 0.2


def _engagement(noise_samples=256, limit="0.5 s", **parameters):
    section = {
        "design": "factorial",
        "options": {"driveline": "rigid"},
        "parameters": {"ramp_time": {"values": ["0.15 s"]}, **parameters},
        "noise": {"friction_coefficient": {"scatter": f"±{100 * SCATTER:g} %"}},
        "noise_samples": noise_samples,
        "objectives": ["slip_work:min", "lockup_time:min"],
        "constraints": {"lockup_time": {"max": limit}},
    }
    section["parameters"].setdefault("friction_coefficient", NOMINAL_MU)
    return resolve({"studies": ["engagement"], "engagement": section})["engagement"]


def _lockup(sec, mu) -> np.ndarray:
    """Lock-up times [s] of the study's nominal design at friction coefficients ``mu``."""
    inputs = dict(sec["fixed"])
    inputs["ramp_time"] = sec["factors"]["ramp_time"]["values"][0]
    inputs["friction_coefficient"] = np.asarray(mu, dtype=float)
    return studies.get("engagement").compute(inputs, sec["options"])["lockup_time"].values


def _run(sec, chunks=1):
    design = doe.build_design(sec)
    parts = [pipeline.run_chunk(design, sec["options"], chunks, i) for i in range(chunks)]
    return pipeline.merge(design, parts)


def test_noise_draws_have_the_corners_first_and_the_same_draws_for_every_design():
    sec = _engagement(noise_samples=8, sheet_thickness={"values": ["2.2 mm", "2.4 mm"]})
    design = doe.build_design(sec)
    d = design["friction_coefficient_noise"].values
    assert design.sizes["noise"] == 2 + 8
    np.testing.assert_array_equal(d[:2], [-SCATTER, SCATTER])
    assert ((d[2:] > -SCATTER) & (d[2:] < SCATTER)).all()
    np.testing.assert_array_equal(design["noise_weight"].values, [0, 0] + [1 / 8] * 8)
    # a scrambled Sobol' sample: one point in each eighth of the interval
    cells = np.floor((d[2:] + SCATTER) / (2 * SCATTER) * 8)
    np.testing.assert_array_equal(np.sort(cells), np.arange(8))
    ds = _run(sec)
    mu = ds["friction_coefficient"].values
    # each scenario ran at the design's mu times (1 + its draw): lock-up at draw k the same as the
    # API's at that mu, for both sheet thicknesses
    got = ds["lockup_time"].isel(sheet_thickness=0).values.reshape(-1)
    want = _lockup(sec | {"fixed": {**sec["fixed"], "sheet_thickness": 2.2e-3}}, mu * (1 + d))
    np.testing.assert_allclose(got, want, rtol=1e-12)


def test_violation_probability_and_worst_case_of_a_closed_form_case():
    """Acceptance: rigid engagement, held engine, mu uniform over ±20 % of 0.35. Lock-up time
    falls monotonically with mu, so P(lock-up > limit) is the share of the mu interval below the
    mu that locks up exactly at the limit (found by bisection to 1e-13 on the API); the estimate
    from 256 scrambled Sobol' draws lies within its Wilson interval (and within 2/256 of it), and
    the worst case equals the lower corner's lock-up to 1e-12."""
    lo, hi = NOMINAL_MU * (1 - SCATTER), NOMINAL_MU * (1 + SCATTER)
    probe = _engagement()
    t_lo, t_hi = _lockup(probe, [lo, hi])
    assert t_lo > t_hi  # monotone: less friction, later lock-up
    limit = float(np.round(t_hi + 0.3 * (t_lo - t_hi), 4))
    sec = _engagement(limit=f"{limit} s")
    a, b = lo, hi  # bisection for the mu locking up exactly at the limit
    for _ in range(80):
        m = 0.5 * (a + b)
        a, b = (m, b) if _lockup(sec, [m])[0] > limit else (a, m)
        if b - a < 1e-13:
            break
    exact = (0.5 * (a + b) - lo) / (hi - lo)
    answers = explore.robust(_run(sec))
    p = float(answers["violation_probability"].squeeze())
    low = float(answers["violation_probability_low"].squeeze())
    high = float(answers["violation_probability_high"].squeeze())
    print(f"P(lock-up > {limit} s): exact {exact:.6f}, estimated {p:.6f} [{low:.4f}, {high:.4f}]")
    assert low <= exact <= high, (low, exact, high)
    assert abs(p - exact) <= 2 / 256, (p, exact)
    worst = float(answers["worst_lockup_time"].squeeze())
    assert worst == pytest.approx(t_lo, rel=1e-12, abs=0)
    assert int(answers["binding_noise"].sel(answer="lockup_time").squeeze()) == 0  # lower corner
    assert float(answers["failure_probability"].squeeze()) == p
    assert int(answers["robust_feasible"].squeeze()) == 0  # 1 % allowed, about 30 % fails


def _brute_rank(f, include):
    """Pareto ranks by peeling non-dominated sets with the O(N²) definition (−1 excluded)."""
    rank = np.full(len(f), -1)
    left = [i for i in range(len(f)) if include[i] and np.isfinite(f[i]).all()]
    r = 0
    while left:
        front = [i for i in left if not any(explore.dominates(f[j], f[i]) for j in left)]
        rank[front] = r
        left = [i for i in left if i not in front]
        r += 1
    return rank


@pytest.mark.parametrize("m", [2, 3, 4])
@pytest.mark.parametrize("which", ["worst", "quantile"])
def test_robust_answers_against_brute_force(m, which):
    """Robust answers of a synthetic crossed result (4×5 designs, 3 conditions, 2 corners and 8
    samples; integer objectives, so ties; failed scenarios) against loops over every design."""
    rng = np.random.default_rng(m)
    shape = (4, 5, 3, 10)
    status = np.where(rng.random(shape) < 0.02, 3, 0).astype(np.int8)
    data = {
        "status": (("a", "b", "load", "noise"), status),
        "noise_weight": ("noise", np.r_[0.0, 0.0, np.full(8, 1 / 8)]),
        "mu_noise": ("noise", np.linspace(-0.2, 0.2, 10), {"units": "1"}),
    }
    for j in range(m):
        v = rng.integers(0, 4, shape).astype(float)
        data[f"y{j}"] = (("a", "b", "load", "noise"), np.where(status == 0, v, np.nan))
    data["c"] = (("a", "b", "load", "noise"), np.where(status == 0, rng.random(shape), np.nan))
    ds = xr.Dataset(
        data, coords={"a": np.arange(4.0), "b": np.arange(5.0), "load": [1.0, 2.0, 3.0]}
    )
    objectives = [f"y{j}:{'min' if j % 2 == 0 else 'max'}" for j in range(m)]
    robust = {
        "conditions": ["load"],
        "quantile": 0.75,
        "max_failure_probability": 0.125,
        "objectives": which,
    }
    got = rb.answers(ds, objectives, {"c": ("max", 0.9)}, robust)
    cols, feasible = np.zeros((20, m)), np.zeros(20, bool)
    for k, (i, j) in enumerate(itertools.product(range(4), range(5))):
        failed = status[i, j] != 0
        bad = failed | ~(ds["c"].values[i, j] <= 0.9)
        p = bad[:, 2:].mean(axis=1)
        np.testing.assert_array_equal(got["failure_probability"].values[i, j], p)
        feasible[k] = (p <= 0.125).all()
        for q, obj in enumerate(objectives):
            name, sense = obj.split(":")
            sign = 1.0 if sense == "min" else -1.0
            y = sign * ds[name].values[i, j]
            per_condition = [np.quantile(y[c, 2:], 0.75, method="inverted_cdf") for c in range(3)]
            worst = np.nan if failed.any() else y.max()
            quant = np.nan if failed.any() else max(per_condition)
            np.testing.assert_array_equal(got[f"worst_{name}"].values[i, j], sign * worst)
            np.testing.assert_array_equal(got[f"quantile_{name}"].values[i, j], sign * quant)
            cols[k, q] = worst if which == "worst" else quant
    np.testing.assert_array_equal(got["robust_feasible"].values.reshape(-1), feasible)
    np.testing.assert_array_equal(
        got["robust_rank"].values.reshape(-1), _brute_rank(cols, feasible)
    )
    assert (got["robust_rank"].values >= 0).any() and (got["robust_rank"].values == -1).any()


def test_binding_condition_and_noise_locate_the_worst_case():
    sec = _engagement(
        noise_samples=8,
        sheet_thickness={"values": ["2.2 mm", "2.4 mm"]},
        driven_inertia={"values": ["0.02 kg*m^2", "0.04 kg*m^2"]},
        load_torque={"values": ["20 N*m", "44 N*m"]},
    )
    ds = _run(sec)
    got = explore.robust(ds)
    assert set(got["robust_rank"].dims) == {"sheet_thickness", "ramp_time"}
    for t in got["sheet_thickness"].values:
        at = dict(
            sheet_thickness=t,
            driven_inertia=float(
                got["binding_driven_inertia"].sel(answer="lockup_time", sheet_thickness=t).squeeze()
            ),
            load_torque=float(
                got["binding_load_torque"].sel(answer="lockup_time", sheet_thickness=t).squeeze()
            ),
            noise=int(got["binding_noise"].sel(answer="lockup_time", sheet_thickness=t).squeeze()),
        )
        worst = float(got["worst_lockup_time"].sel(sheet_thickness=t).squeeze())
        assert float(ds["lockup_time"].sel(at).squeeze()) == worst
        assert worst == float(ds["lockup_time"].sel(sheet_thickness=t).max())
    # the heavier inertia and the higher load lock up last, at the lowest friction (corner 0)
    assert (got["binding_driven_inertia"].sel(answer="lockup_time") == 0.04).all()
    assert (got["binding_load_torque"].sel(answer="lockup_time") == 44.0).all()
    assert (got["binding_friction_coefficient_noise"].sel(answer="lockup_time") == -SCATTER).all()


def test_robust_answers_are_identical_for_one_chunk_and_seven(tmp_path):
    sec = _engagement(
        noise_samples=8,
        sheet_thickness={"values": ["2.2 mm", "2.4 mm", "2.6 mm"]},
        driven_inertia={"values": ["0.02 kg*m^2", "0.04 kg*m^2"]},
    )
    design = doe.build_design(sec)
    results = []
    for chunks in (1, 7):
        paths = []
        for i in range(chunks):
            paths.append(tmp_path / f"chunk_{chunks}_{i}.h5")
            store.write(
                pipeline.run_chunk(design, sec["options"], chunks, i), paths[-1], with_checksum=True
            )
        out, robust_path = tmp_path / f"out_{chunks}.h5", tmp_path / f"robust_{chunks}.h5"
        pipeline.merge_to_file(
            design, paths, out, sec["objectives"], sec["constraints"], robust_path=robust_path
        )
        results.append(store.load_verified(robust_path))
    xr.testing.assert_identical(results[0], results[1])
    xr.testing.assert_identical(results[0].drop_attrs(), explore.robust(_run(sec)).drop_attrs())


def test_a_study_without_robust_keys_is_unchanged():
    """Existing configs: no noise dimension, no robust section, the same config text."""
    sec = resolve(
        {
            "studies": ["engagement"],
            "engagement": {
                "design": "factorial",
                "parameters": {"ramp_time": {"values": [0.1, 0.2]}},
            },
        }
    )["engagement"]
    assert "robust" not in sec
    assert "noise" not in doe.build_design(sec).dims
    with pytest.raises(ValueError, match="not a robust study"):
        explore.robust(_run(sec))


def test_wilson_interval_against_its_closed_form():
    """Wilson (1927): for k = 0 the bounds are 0 and z²/(n + z²)."""
    lo, hi = rb.wilson_interval(0, 100)
    z = 1.959963984540054
    assert lo == 0.0 and hi == pytest.approx(z * z / (100 + z * z), rel=1e-12)
    lo, hi = rb.wilson_interval(50, 100)
    assert 0.5 - lo == pytest.approx(hi - 0.5, rel=1e-12)


def test_sampled_design_points_crossed_and_refined_near_the_robust_front(tmp_path):
    """Sobol design points × a condition grid × noise draws: merged by file (3 chunks) as in
    memory; a refining stage samples near the robust front, with the first stage's conditions
    and the same noise draws."""
    raw = {
        "design": "sobol",
        "samples": 16,
        "seed": 3,
        "options": {"driveline": "rigid"},
        "parameters": {
            "sheet_thickness": {"min": "2.1 mm", "max": "2.6 mm"},
            "ramp_time": {"min": "0.05 s", "max": "0.3 s"},
            "driven_inertia": {"values": ["0.021 kg*m^2", "0.05 kg*m^2"]},
        },
        "noise": {"friction_coefficient": {"scatter": "±20 %"}},
        "noise_samples": 8,
    }
    sec = resolve({"studies": ["engagement"], "engagement": raw})["engagement"]
    design = doe.build_design(sec)
    assert dict(design.sizes) == {"point": 16, "driven_inertia": 2, "noise": 10}
    paths = []
    for i in range(3):
        paths.append(tmp_path / f"chunk_{i}.h5")
        store.write(pipeline.run_chunk(design, sec["options"], 3, i), paths[-1], with_checksum=True)
    first = tmp_path / "engagement.h5"
    pipeline.merge_to_file(
        design, paths, first, sec["objectives"], sec["constraints"], robust_path=tmp_path / "r.h5"
    )
    answers = store.load_verified(tmp_path / "r.h5")
    assert answers["robust_rank"].dims == ("point",)
    np.testing.assert_array_equal(answers["sheet_thickness"].values, design["sheet_thickness"])
    merged = pipeline.merge(design, [store.load(p) for p in paths])
    xr.testing.assert_identical(answers.drop_attrs(), explore.robust(merged).drop_attrs())
    refine = {"design": "refine", "refine": {"from": str(first)}, "samples": 8, "seed": 1}
    second = resolve(
        {"studies": ["engagement"], "results": str(tmp_path / "second"), "engagement": refine}
    )["engagement"]
    d2 = doe.build_design(second)
    assert dict(d2.sizes) == {"point": 8, "driven_inertia": 2, "noise": 10}
    np.testing.assert_array_equal(
        d2["friction_coefficient_noise"].values, design["friction_coefficient_noise"].values
    )
    np.testing.assert_array_equal(d2["driven_inertia"].values, design["driven_inertia"].values)
    # each new design lies within the box around a robust front design
    h = d2["sheet_thickness"].attrs["refine_halfwidth"] * (2.6e-3 - 2.1e-3)
    front = answers["sheet_thickness"].values[answers["robust_rank"].values == 0]
    gap = np.abs(d2["sheet_thickness"].values[:, None] - front[None, :]).min(axis=1)
    assert (gap <= h * (1 + 1e-9)).all()
    _check_robust_refinement(tmp_path, answers, d2, second)


def _check_robust_refinement(tmp_path, answers, d2, second):
    """The refining stage's robust front against the first stage's: counts of robust-feasible
    designs, the joint front's members from the second stage by brute-force dominance, and the
    refinement page saying it compares robust fronts."""
    from clutchlab.report import answers as answer_pages

    chunk = tmp_path / "second_chunk.h5"
    store.write(pipeline.run_chunk(d2, second["options"], 1, 0), chunk, with_checksum=True)
    pipeline.merge_to_file(
        d2,
        [chunk],
        tmp_path / "second.h5",
        second["objectives"],
        second["constraints"],
        robust_path=tmp_path / "r2.h5",
    )
    a2 = store.load_verified(tmp_path / "r2.h5")
    v1, v2 = rb.front_view(answers), rb.front_view(a2, {"refine_from": "first.h5"})
    gain = explore.refinement_gain(v1, v2)
    assert int(gain["feasible_first"][0]) == int(answers["robust_feasible"].sum())
    assert int(gain["feasible_second"][0]) == int(a2["robust_feasible"].sum())
    assert float(gain["hypervolume_after"][0]) >= float(gain["hypervolume_before"][0])
    which = answers.attrs["robust_objectives"]
    cols = [f"{which}_{o}" for o in ("slip_work", "peak_jerk")]
    assert v1["pareto_rank"].attrs["objectives"].split() == [f"{c}:min" for c in cols]
    f = np.concatenate(
        [
            np.stack([a[c].values[a["robust_feasible"].values == 1] for c in cols], 1)
            for a in (answers, a2)
        ]
    )
    n1 = int(answers["robust_feasible"].sum())
    dominated = [
        any((g <= p).all() and (g < p).any() for g in f) for p in f
    ]  # brute force over the joint feasible set
    assert int(gain["front_from_second"][0]) == sum(not d for d in dominated[n1:])
    fig = answer_pages.refinement_page("engagement", v1, v2, gain)
    assert "robust front" in fig._suptitle.get_text()


@pytest.mark.slow
def test_the_binding_answer_is_the_constraint_of_the_least_worst_margin():
    """Of two constraints the one a design misses most binds it, whichever is listed first: the
    pages and the traces locate that one's worst case and name it."""
    from clutchlab.report import robust as pages

    raw = {
        "studies": ["engagement"],
        "engagement": {
            "design": "factorial",
            "options": {"driveline": "rigid"},
            "parameters": {
                "ramp_time": {"values": ["0.15 s"]},
                "sheet_thickness": {"values": ["2.2 mm", "2.4 mm"]},
                "friction_coefficient": NOMINAL_MU,
            },
            "noise": {"friction_coefficient": {"scatter": "±20 %"}},
            "noise_samples": 8,
            "objectives": ["slip_work:min", "lockup_time:min"],
            "constraints": {"lockup_time": {"max": "0.5 s"}, "slip_work": {"max": "1 J"}},
        },
    }
    sec = resolve(raw)["engagement"]
    got = explore.robust(_run(sec))
    assert str(got["constraint"].values[0]) == "lockup_time"
    margins = got["worst_margin"].transpose("constraint", *got["robust_rank"].dims).values
    for j in range(got["robust_rank"].size):
        m = margins.reshape(2, -1)[:, j]
        assert m[1] < m[0]  # 1 J of slip work: missed by far more than the lock-up limit
        assert explore.binding_answer(got, j) == "slip_work"
        assert explore.robust_scenario(_run(sec), got, j)[1] == "slip_work"
        assert pages.binding_text(got, j).startswith("slip_work worst at ")


def test_the_default_runs_best_robust_design_meets_every_limit_through_the_api():
    """Acceptance: the default study's engagement (config/config.yaml, a crossed robust study),
    its best robust design called through the API at every operating condition and at both ends
    of its friction coefficient's ±20 % interval meets every constraint; the binding condition is
    the one where its margin is least."""
    from pathlib import Path

    from clutchlab import config

    sec = config.load(Path(__file__).parents[1] / "config" / "config.yaml")["engagement"]
    ds = _run(sec)
    answers = explore.robust(ds)
    j = explore.best_robust(answers)
    assert j is not None
    at = np.unravel_index(j, answers["robust_rank"].shape)
    design = {
        d: float(answers[d].values[i]) for d, i in zip(answers["robust_rank"].dims, at, strict=True)
    }
    study = studies.get("engagement")
    margins = {}
    for inertia, load, end in itertools.product(
        ds["driven_inertia"].values, ds["load_torque"].values, (-SCATTER, SCATTER)
    ):
        inputs = {**sec["fixed"], **design, "driven_inertia": inertia, "load_torque": load}
        inputs["friction_coefficient"] = design["friction_coefficient"] * (1 + end)
        out = study.compute({k: np.atleast_1d(v) for k, v in inputs.items()}, sec["options"])
        assert int(out["status"].values[0]) == 0
        for output, (op, limit) in sec["constraints"].items():
            v = float(out[output].values[0])
            margins[(inertia, load, end)] = explore.constraint_margin(v, op, limit)
            assert margins[(inertia, load, end)] >= 0, (output, v, inertia, load, end)
    worst = min(margins, key=margins.get)
    binding = answers.isel(dict(zip(answers["robust_rank"].dims, at, strict=True)))
    answer = str(list(sec["constraints"])[0])
    assert float(binding["binding_driven_inertia"].sel(answer=answer)) == worst[0]
    assert float(binding["binding_load_torque"].sel(answer=answer)) == worst[1]
    assert float(binding["binding_friction_coefficient_noise"].sel(answer=answer)) == worst[2]
    # its robust page: legible (8 pt and up), every text on the page and in its table cell
    import matplotlib.pyplot as plt

    from clutchlab.report import robust as pages
    from clutchlab.report.common import texts_outside, texts_outside_cells, texts_too_small

    # the front's table names the constraint that binds each design beside where it binds
    header, rows = pages.front_rows(answers)
    assert header[-2] == "binding constraint" and header[-1].startswith("worst at ")
    front = np.flatnonzero(answers["robust_rank"].values.reshape(-1) == 0)
    assert sorted(r[-2] for r in rows) == sorted(explore.binding_answer(answers, k) for k in front)
    fig = pages.page("engagement", answers)
    assert not texts_too_small(fig), texts_too_small(fig)[:5]
    assert not texts_outside(fig) and not texts_outside_cells(fig), texts_outside_cells(fig)
    plt.close(fig)


_OTHER_STUDIES = {
    "sprag": {
        "torque": {"values": ["500 N*m", "750 N*m"], "role": "condition"},
        "sprags": {"values": [18, 22]},
        "sprag_length": {"values": ["18 mm", "22 mm"]},
    },
    "roller": {
        "rollers": {"values": [8, 12]},
        "wedge_angle": {"values": ["8 deg", "12 deg"]},
        "friction_coefficient": {"values": [0.1, 0.12]},
    },
    "diaphragm_spring": {
        "sheet_thickness": {"values": ["2.3 mm", "2.6 mm"]},
        "cone_height_ratio": {"values": [1.5, 1.7]},
    },
}


@pytest.mark.parametrize("name", sorted(_OTHER_STUDIES))
def test_robust_answers_of_the_sprag_roller_and_diaphragm_studies(name):
    """The study's default noise (sprag geometry, roller mu and diameter, spring sheet and cone
    tolerances) on a small grid: the failure probability per design and condition is the share of
    the weighted samples whose status is not ok or that violate a constraint, computed here from
    the stored scenarios; robust_feasible follows from it and the limit; a robust rank only where
    robust-feasible; the worst margin is the least over conditions and every draw."""
    sec = resolve(
        {
            "studies": [name],
            name: {
                "design": "factorial",
                "robust": True,
                "noise_samples": 8,
                "parameters": _OTHER_STUDIES[name],
            },
        }
    )[name]
    ds = pipeline.run_study(sec)
    ans = explore.robust(ds)
    design = list(ans["robust_rank"].dims)
    conds = [d for d in ds["status"].dims if d not in design and d != "noise"]
    w = ds["noise_weight"] > 0
    margins = ds["constraint_margin"]
    bad = (ds["status"] != 0) | (margins < 0).any("constraint") | margins.isnull().any("constraint")
    share = bad.where(w).sum("noise") / w.sum()
    got = ans["failure_probability"].transpose(*design, *conds)
    np.testing.assert_allclose(got.values, share.transpose(*design, *conds).values, atol=1e-12)
    limit = float(sec["robust"]["max_failure_probability"])
    feasible = (share <= limit).all(conds) if conds else share <= limit
    np.testing.assert_array_equal(ans["robust_feasible"].values.astype(bool), feasible.values)
    assert ((ans["robust_rank"] >= 0) == feasible).all()
    worst = margins.min(["noise", *conds], skipna=False)
    got = ans["worst_margin"]
    worst = worst.sel(constraint=got["constraint"].values).transpose(*got.dims)
    ok = np.isfinite(got.values)
    assert not (ok & np.isnan(worst.values)).any()  # NaN wherever a scenario has no margin
    assert ok.any() or name == "roller"  # (no roller design of this grid survives every draw)
    np.testing.assert_allclose(got.values[ok], worst.values[ok], rtol=1e-12)


def test_the_robust_page_says_what_its_draw_count_can_resolve():
    """Wilson score interval for 0 failures in n draws: upper bound z²/(n + z²) (z = 1.95996 at
    95 %); 64 draws bound a clean design at 5.7 %, and a 1 % bound takes n ≥ z²·0.99/0.01 = 380.3,
    so 381 draws."""
    from clutchlab.report import robust as pages

    ra = xr.Dataset(attrs={"noise_samples": 64, "max_failure_probability": 0.01})
    text = pages.resolution_text(ra)
    assert "up to 5.7 %" in text and "381 draws" in text
    ra.attrs["noise_samples"] = 512  # resolves 1 %: no advice
    assert "0.74 %" in pages.resolution_text(ra)
    assert "draws or more" not in pages.resolution_text(ra)


def test_the_summary_of_a_robust_study_without_a_robust_design_says_so_once():
    """No design meets the limit under the scatter: the summary's line says "none" and why, not
    "no robust design" twice; the noise parameters are listed with commas."""
    from clutchlab.report import robust as pages

    sec = _engagement(noise_samples=8, limit="1 ms")
    ra = explore.robust(_run(sec))
    ra.attrs["noise_parameters"] = "friction_coefficient roller_diameter"
    head, best = pages.summary_lines(ra)
    assert "noise samples of friction_coefficient, roller_diameter;" in head
    assert best.startswith("best robust design: none (no design fails in at most 1 % of its")
    assert best.count("no robust design") == 0


def _twelve_conditions():
    """A robust engagement study of twelve operating conditions (3 inertias × 4 loads), four
    designs and two noise samples of μ (with the corners, six draws)."""
    return resolve(
        {
            "studies": ["engagement"],
            "engagement": {
                "design": "factorial",
                "robust": True,
                "noise_samples": 2,
                "parameters": {
                    "ramp_time": {"values": ["0.08 s", "0.15 s"]},
                    "friction_coefficient": {"values": [0.38, 0.42]},
                    "sheet_thickness": "2.45 mm",
                    "driven_inertia": {"values": ["0.02 kg*m^2", "0.035 kg*m^2", "0.05 kg*m^2"]},
                    "load_torque": {"values": ["30 N*m", "50 N*m", "70 N*m", "90 N*m"]},
                },
            },
        }
    )["engagement"]


def test_the_robust_page_names_its_conditions_legibly_and_where_each_design_binds():
    """Twelve operating conditions: their two-line names would overprint side by side, so one
    in k is named (the title says so); the front table shows where each design binds, the noise
    draw on a line of its own where the rows fit (it was cut to "[...]")."""
    import matplotlib.pyplot as plt

    from clutchlab.report import robust as pages
    from clutchlab.report.common import texts_outside, texts_outside_cells

    answers = explore.robust(_run(_twelve_conditions()))
    fig = pages.page("engagement", answers)
    fig.canvas.draw()
    ax = next(a for a in fig.axes if a.get_title().startswith("best robust design at each"))
    named = [t.get_text() for t in ax.get_xticklabels() if t.get_text()]
    k = int(ax.get_title().split("(one in ")[1].split(" ")[0])
    assert k > 1 and len(named) == -(-12 // k) and "0.02 kg·m²\n30 N·m" in named
    # every mark its legend names is drawn (robust-feasible: those off the front)
    front_ax = next(a for a in fig.axes if a.get_xlabel().startswith("worst slip work"))
    assert all(len(c.get_offsets()) for c in front_ax.collections)
    names = [t.get_text() for t in front_ax.get_legend().get_texts()]
    assert ("robust-feasible" in names) == bool(
        (answers["robust_feasible"] & (answers["robust_rank"] != 0)).any()
    )
    assert not texts_outside(fig) and not texts_outside_cells(fig), texts_outside_cells(fig)
    table_ax = next(a for a in fig.axes if a.tables)
    header, rows = pages.front_rows(answers)
    for n, lines in ((2, 3), (4, 2), (8, 1)):  # (two rows fit three lines each, four two)
        ax = fig.add_axes(table_ax.get_position())
        pages._front_table(ax, header, (rows * 8)[:n])
        cells = ax.tables[0].get_celld()
        last = max(col for _, col in cells)
        texts = [c.get_text().get_text() for (r, col), c in cells.items() if r and col == last]
        assert all(t.count("\n") == lines - 1 for t in texts), (n, texts)
        if lines == 3:  # the noise draw whole on its own line
            assert all(t.endswith("friction_coefficient -20.0 %") for t in texts), texts
        ax.remove()
    plt.close(fig)


def test_the_answers_page_of_a_robust_study_gives_each_noise_draw_by_its_deviation():
    """The answers page's front table gave a robust result's noise draw by its index ("noise [-]",
    0-5: it read as a value); it gives the draw's deviation of μ in % (the CSV the index too).
    The fronts' legend is beside the panel (inside it hid the fronts), the designs beyond the
    axes are counted in it (a note on the panel printed over points and the star), the table
    shows the rows that fit (they were squeezed until their text overprinted), and the jerk axis
    carries its power of ten in its label (a bare "1e6" at its end)."""
    import matplotlib.pyplot as plt

    from clutchlab.report import answers as page
    from clutchlab.report.common import (
        fold_multipliers,
        legends_over_data,
        texts_outside,
        texts_outside_cells,
        texts_overprinted,
    )

    sec = _twelve_conditions()
    ds = explore.annotate(_run(sec), sec["objectives"], sec["constraints"])
    header, rows = page.front_rows(ds)
    i = header.index("noise [-]")
    assert header[i + 1] == "friction_coefficient_noise [%]"
    deviation = ds["friction_coefficient_noise"].values
    assert {round(r[i]) for r in rows} > {0, 1}  # (corners and samples among the front's draws)
    for r in rows:
        assert r[i + 1] == pytest.approx(100 * deviation[round(r[i])], rel=1e-12)
    shown_header, _ = page.front_rows(ds, typeset=True)
    assert "noise [-]" not in shown_header and "friction_coefficient_noise [%]" in shown_header
    fig = page.page("engagement", ds)
    fold_multipliers(fig)
    front = next(a for a in fig.axes if a.get_xlabel().startswith("slip_work"))
    assert front.get_legend() is None and not front.texts
    assert front.get_ylabel().startswith("peak_jerk [10⁶ rad/s³]")
    assert not front.yaxis.get_offset_text().get_text()
    table = next(a for a in fig.axes if a.tables)
    texts = [c.get_text().get_text() for c in table.tables[0].get_celld().values()]
    assert any("noise" in t and "[%]" in t for t in texts)
    assert not any(t.startswith("noise") for t in texts)
    assert not legends_over_data(fig), legends_over_data(fig)
    assert not texts_outside(fig) and not texts_overprinted(fig)
    assert not texts_outside_cells(fig), texts_outside_cells(fig)
    plt.close(fig)


@pytest.mark.parametrize(
    "kwargs, word",
    [
        ({"conditions": ["nonexistent"]}, "conditions"),
        ({"conditions": "driven_inertia"}, "conditions"),
        ({"quantile": "0.9"}, "quantile"),
        ({"quantile": 1.5}, "quantile"),
        ({"max_failure_probability": -1}, "max_failure_probability"),
        ({"objectives": "best"}, "objectives"),
        ({"objectives": ["lockup_time:mni"]}, "objective"),
        ({"constraints": {"lockup_time": ("<", 0.3)}}, "constraint"),
        ({"qantile": 0.9}, "unknown robust setting"),
    ],
)
def test_robust_refuses_a_setting_that_is_not_one(kwargs, word):
    """explore.robust dropped an unknown condition without a word (its answers then over design ×
    condition), took "<" for a minimum and a typo in a sense for a maximum, and failed on a text
    quantile with a numpy error; each is refused naming it. "worst" or "quantile" given as the
    objectives is the robust setting (it shares the keyword)."""
    ds = _run(_engagement(noise_samples=2, ramp_time={"values": ["0.1 s", "0.2 s"]}))
    with pytest.raises(ValueError, match=word):
        explore.robust(ds, **kwargs)
    ranked = explore.robust(ds, "quantile")
    assert ranked["robust_rank"].attrs["robust_objectives"] == "quantile"
