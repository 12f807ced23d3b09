"""Design answers (issue 15): Pareto ranks and hypervolume against brute force (O(N^2) peeling,
inclusion-exclusion), feasibility, the grid's exact variance decomposition against analytic
examples."""

import itertools

import numpy as np
import pytest
import xarray as xr

from clutchlab import explore
from clutchlab import status as st


def _brute_ranks(f, include):
    """O(N^2) peeling: rank k = non-dominated among what is left after ranks < k."""
    n = len(f)
    ok = np.isfinite(f).all(axis=1) & include
    rank = np.full(n, -1)
    left = set(np.flatnonzero(ok).tolist())
    k = 0
    while left:
        front = [i for i in left if not any(explore.dominates(f[j], f[i]) for j in left if j != i)]
        for i in front:
            rank[i] = k
        left -= set(front)
        k += 1
    return rank


@pytest.mark.parametrize("m", [1, 2, 3, 4, 5])
def test_pareto_rank_equals_brute_force(m):
    """Random integer objectives (many ties and duplicate rows), NaN and ±inf rows and excluded
    rows: every rank equal to the O(N^2) peeling."""
    rng = np.random.default_rng(m)
    for _ in range(150):
        n = int(rng.integers(1, 70))
        f = rng.integers(0, 5, (n, m)).astype(float)
        if rng.random() < 0.5:
            f[rng.integers(0, n), rng.integers(0, m)] = np.nan
        if rng.random() < 0.3:
            f[rng.integers(0, n), rng.integers(0, m)] = rng.choice([np.inf, -np.inf])
        include = rng.random(n) < 0.85
        assert (explore.pareto_rank(f, include) == _brute_ranks(f, include)).all()


def test_a_nan_row_neither_dominates_nor_is_ranked():
    """moocore alone ranks a NaN row as dominating (the rows it would dominate fall to rank 1);
    the wrapper leaves it out: −1, and the other rows keep their front. -inf is no better."""
    f = np.array([[1.0, 2.0], [np.nan, 0.0], [0.5, 3.0], [-np.inf, -np.inf]])
    assert explore.pareto_rank(f).tolist() == [0, -1, 0, -1]


@pytest.mark.parametrize("m", [2, 3, 4, 5])
def test_grouped_ranks_with_ties_and_nan_equal_brute_force(m):
    """Groups (ints, floats with a NaN label, strings): each group ranked on its own, equal to the
    peeling of that group alone; a row with a NaN group label belongs to no group (−1)."""
    rng = np.random.default_rng(20 + m)
    f = rng.integers(0, 4, size=(300, m)).astype(float)
    f[rng.integers(0, 300, 10), rng.integers(0, m, 10)] = np.nan
    include = rng.random(300) > 0.1
    codes = rng.integers(0, 5, size=300)
    for labels in (codes, codes * 0.5, np.array(list("abcde"))[codes]):
        got = explore.pareto_rank(f, include, labels)
        for g in np.unique(labels):
            sel = labels == g
            assert (got[sel] == _brute_ranks(f[sel], include[sel])).all()
    floats = np.where(codes == 4, np.nan, codes * 1.0)
    got = explore.pareto_rank(f, include, floats)
    assert (got[codes == 4] == -1).all()
    assert (got[codes == 0] == _brute_ranks(f[codes == 0], include[codes == 0])).all()


def test_pareto_rank_refuses_misshaped_inputs():
    f = np.zeros((4, 2))
    with pytest.raises(ValueError, match=r"\(designs, objectives\)"):
        explore.pareto_rank(np.zeros(4))
    with pytest.raises(ValueError, match="include must have one entry per row of values"):
        explore.pareto_rank(f, include=[True])
    with pytest.raises(ValueError, match="groups must have one entry per row of values"):
        explore.pareto_rank(f, groups=[0, 1, 2])


def test_dataset_form_maximises_and_minimises():
    """ "name:max" ranks the negated column: the ranks of the array form on (a, −b), within each
    value of the condition c, over the rows with status ok."""
    rng = np.random.default_rng(4)
    a, b = rng.integers(0, 4, 60).astype(float), rng.integers(0, 4, 60).astype(float)
    c = rng.integers(0, 2, 60).astype(float)
    status = np.where(rng.random(60) < 0.2, st.CODE["invalid_input"], st.CODE["ok"])
    ds = xr.Dataset(
        {
            "a": ("run", a, {"units": "1", "long_name": "a"}),
            "b": ("run", b, {"units": "1", "long_name": "b"}),
            "c": ("run", c, {"units": "1", "long_name": "c"}),
            "status": ("run", status.astype(np.int8), {"units": "1", "long_name": "status"}),
        }
    )
    got = explore.pareto_rank(ds, ["a:min", "b:max"], ["c"]).values
    ok = status == st.CODE["ok"]
    f = np.stack([a, -b], axis=1)
    for k in (0.0, 1.0):
        sel = c == k
        assert (got[sel] == _brute_ranks(f[sel], ok[sel])).all()


def _inclusion_exclusion(points, ref):
    """Hypervolume by inclusion-exclusion over every subset of the points (exact, 2^N terms)."""
    p = np.asarray(points, dtype=float)
    total = 0.0
    for k in range(1, len(p) + 1):
        for subset in itertools.combinations(range(len(p)), k):
            corner = p[list(subset)].max(axis=0)
            total += (-1) ** (k + 1) * np.prod(np.clip(ref - corner, 0.0, None))
    return total


@pytest.mark.parametrize("m", [1, 2, 3, 4, 5])
def test_hypervolume_equals_inclusion_exclusion(m):
    """Continuous points with ties in a coordinate, repeated and dominated points and points
    beyond the reference in one objective, 1 to 5 objectives: relative 1e-12."""
    rng = np.random.default_rng(30 + m)
    ref = rng.uniform(1.0, 2.0, m)
    for _ in range(25):
        n = int(rng.integers(1, 11))
        p = rng.random((n, m)) * 1.3
        p[rng.random((n, m)) < 0.15] = 0.5  # ties
        if n > 2:
            p[-1] = p[0]  # a repeated point
        exact = _inclusion_exclusion(p, ref)
        assert explore.hypervolume(p, ref) == pytest.approx(exact, rel=1e-12, abs=1e-15)


def test_hypervolume_refuses_what_it_cannot_measure():
    """Points of another width than the reference (ValueError naming both widths; no silent
    reshape), non-finite points or reference; an empty set is 0."""
    with pytest.raises(ValueError, match="reference's 2 objectives, got 3 objectives"):
        explore.hypervolume(np.zeros((2, 3)), [1.0, 1.0])
    with pytest.raises(ValueError, match="reference's 3 objectives, got 2 objectives"):
        explore.hypervolume(np.zeros((3, 2)), [1.0, 1.0, 1.0])
    with pytest.raises(ValueError, match="got shape"):
        explore.hypervolume(np.zeros(6), [1.0, 1.0])
    with pytest.raises(
        ValueError, match=r"2 of 3 points have a non-finite objective \(first: row 1"
    ):
        explore.hypervolume([[0.5, 0.5], [np.inf, 0.1], [0.2, np.nan]], [1.0, 1.0])
    with pytest.raises(ValueError, match="reference must be a finite point"):
        explore.hypervolume([[0.5, 0.5]], [1.0, np.nan])
    with pytest.raises(ValueError, match="overflows"):
        explore.hypervolume([[-1e200, -1e200]], [1e200, 1e200])
    assert explore.hypervolume(np.empty((0, 4)), np.ones(4)) == 0.0


@pytest.mark.parametrize("m", [2, 3, 4, 5])
def test_pareto_rank_on_continuous_data(m):
    rng = np.random.default_rng(10 + m)
    f = rng.random((400, m))
    assert (explore.pareto_rank(f) == _brute_ranks(f, np.ones(400, bool))).all()


def test_pareto_front_of_a_known_set():
    f = np.array([[1, 5], [2, 3], [3, 1], [2, 4], [4, 4], [2, 3], [5, 5]], float)
    assert explore.pareto_rank(f).tolist() == [0, 0, 0, 1, 2, 0, 3]  # duplicates share the front


def test_feasible_and_margins():
    ds = xr.Dataset(
        {
            "status": ("run", np.array([0, 0, 4, 0], np.int8)),
            "slip_work": ("run", np.array([5000.0, 7000.0, np.nan, 6000.0])),
            "reserve_factor": ("run", np.array([1.3, 1.5, 1.4, 1.1])),
        }
    )
    ok, margins = explore.feasible(
        ds, {"slip_work": ("max", 6500.0), "reserve_factor": ("min", 1.2)}
    )
    assert ok.tolist() == [True, False, False, False]
    # capacity over demand minus one: 6500/5000 − 1 under a maximum, 1.1/1.2 − 1 over a minimum
    assert margins["slip_work"][0] == pytest.approx(6500 / 5000 - 1) and np.isnan(
        margins["slip_work"][2]
    )
    assert margins["reserve_factor"][3] == pytest.approx(1.1 / 1.2 - 1)
    assert ds["status"].values[2] == st.CODE["never_locked"]


def test_grid_decomposition_additive_and_interaction():
    """y = a·x1 + b·x2 + c·x1·x2 on a centred grid of x1, x2 ∈ {−1, 1}: with equal weights
    Var = a² + b² + c²; S1 = a²/Var, S2 = b²/Var, ST1 = (a² + c²)/Var, ST2 = (b² + c²)/Var;
    additive (c = 0): S = ST exactly, and a third factor that does nothing has S = ST = 0."""
    a, b, c = 2.0, 1.0, 0.5
    x1 = np.array([-1.0, 1.0])[:, None, None]
    x2 = np.array([-1.0, 1.0])[None, :, None]
    x3 = np.array([0.0, 1.0, 2.0])[None, None, :]
    y = a * x1 + b * x2 + c * x1 * x2 + 0.0 * x3
    y = np.broadcast_to(y, (2, 2, 3))
    d = explore.grid_variance_decomposition(y, ["x1", "x2", "x3"])
    var = a**2 + b**2 + c**2
    assert d["variance"] == pytest.approx(var)
    assert d["first_order"]["x1"] == pytest.approx(a**2 / var) and d["total"][
        "x1"
    ] == pytest.approx((a**2 + c**2) / var)
    assert d["first_order"]["x2"] == pytest.approx(b**2 / var) and d["total"][
        "x2"
    ] == pytest.approx((b**2 + c**2) / var)
    assert d["first_order"]["x3"] == 0.0 and d["total"]["x3"] == 0.0
    add = explore.grid_variance_decomposition(
        np.broadcast_to(a * x1 + b * x2, (2, 2, 3)), ["x1", "x2", "x3"]
    )
    for k in ("x1", "x2"):
        assert add["first_order"][k] == pytest.approx(add["total"][k], abs=1e-15)


@pytest.mark.parametrize(
    "name, section",
    [
        (
            "centrifugal",
            {
                "design": "factorial",
                "parameters": {
                    "pressure_angle": {"values": ["25 deg", "38.84 deg", "53 deg", "65 deg"]},
                    "friction_coefficient": {"values": [0.3, 0.35, 0.4046, 0.5, 0.6]},
                },
            },
        ),
        (
            "sprag",
            {
                "design": "factorial",
                "parameters": {
                    "torque": {"values": ["267.5 N*m", "500 N*m", "750 N*m"]},
                    "sprags": {"values": [14, 16, 18, 20]},
                },
            },
        ),
        (
            "engagement",
            {
                "design": "sobol",
                "samples": 16,
                "options": {"driveline": "compliant"},
                # (the window covers the longest ramp: a config refuses end_time <= ramp_time)
                "parameters": {
                    "ramp_time": {"min": "0.05 s", "max": "1.5 s"},
                    "end_time": "1.6 s",
                },
            },
        ),
    ],
)
def test_every_study_result_answers(name, section):
    """A study result carries feasible, constraint_margin and pareto_rank (with the objectives it
    ranks), consistent with each other: feasible = status ok and every margin >= 0; ranked =
    feasible with finite objectives; rank 0 = the brute-force front of the feasible designs."""
    from clutchlab import pipeline
    from clutchlab.config import resolve

    sec = resolve({"studies": [name], name: section})[name]
    ds = pipeline.run_study(sec)
    dims = ds["status"].dims
    assert ds["feasible"].dims == dims and ds["pareto_rank"].dims == dims
    assert ds["constraint_margin"].dims == ("constraint",) + dims
    assert list(ds["constraint"].values) == list(sec["constraints"])
    assert ds["pareto_rank"].attrs["objectives"] == " ".join(sec["objectives"])
    ok = (ds["status"] == st.CODE["ok"]) & (ds["constraint_margin"] >= 0).all("constraint")
    assert (ds["feasible"] == ok).all()
    f = np.stack(
        [
            (ds[o.split(":")[0]] * (1 if o.endswith(":min") else -1)).values.reshape(-1)
            for o in sec["objectives"]
        ],
        axis=1,
    )
    feas = ds["feasible"].values.reshape(-1).astype(bool)
    assert feas.any() and not feas.all()  # a question with an answer
    assert (
        (ds["pareto_rank"].values.reshape(-1) >= 0) == (feas & np.isfinite(f).all(axis=1))
    ).all()
    # rank 0 = the brute-force front of the feasible designs sharing the operating conditions
    within = ds["pareto_rank"].attrs["ranked_within"].split()
    assert within == (
        ["torque"] if name == "sprag" else []
    )  # the sprag torque is a load, not a choice
    key = (
        np.stack([ds[w].broadcast_like(ds["status"]).values.reshape(-1) for w in within], axis=1)
        if within
        else np.zeros((f.shape[0], 1))
    )
    front = np.zeros(f.shape[0], bool)
    for k in np.unique(key, axis=0):
        g = (key == k).all(axis=1)
        front[g] = _brute_ranks(f[g], feas[g]) == 0
    assert len(np.unique(key, axis=0)) == (3 if within else 1)
    assert ((ds["pareto_rank"].values.reshape(-1) == 0) == front).all()
    for name_, var in {**ds.coords, **ds.data_vars}.items():
        assert "units" in var.attrs and "long_name" in var.attrs, name_


def test_grouped_ranks_are_ranks_within_each_group():
    """pareto_rank(groups=...) ranks each group on its own: equal to ranking the groups one by one,
    and a design is never dominated by one of another group."""
    rng = np.random.default_rng(3)
    f = rng.integers(0, 5, size=(600, 2)).astype(float)
    groups = rng.integers(0, 7, size=600)
    include = rng.random(600) > 0.1
    got = explore.pareto_rank(f, include, groups)
    for g in range(7):
        sel = groups == g
        assert (got[sel] == _brute_ranks(f[sel], include[sel])).all()


def _engagement_over_two_loads():
    """A rigid engagement grid over ramp time, mu and two load torques: (resolved section, result)."""
    from clutchlab import pipeline
    from clutchlab.config import resolve

    section = {
        "design": "factorial",
        "options": {"driveline": "rigid"},
        "parameters": {
            "ramp_time": {"values": ["0.05 s", "0.1 s", "0.2 s", "0.3 s"]},
            "friction_coefficient": {"values": [0.3, 0.35, 0.4]},
            "load_torque": {"values": ["44 N*m", "80 N*m"]},
        },
    }
    sec = resolve({"studies": ["engagement"], "engagement": section})["engagement"]
    return sec, pipeline.run_study(sec)


def test_operating_conditions_are_not_design_choices():
    """An engagement grid over the load torque: without grouping, every front design would carry the
    lightest load (it always needs less slip work); ranked within each load torque, each load has
    its own front. A sampled load torque cannot be grouped and is named in conditions_mixed."""
    from clutchlab import pipeline
    from clutchlab.config import resolve

    sec, ds = _engagement_over_two_loads()
    assert ds["pareto_rank"].attrs["ranked_within"] == "load_torque"
    front = ds["pareto_rank"] == 0
    assert front.sel(load_torque=80.0).any() and front.sel(load_torque=44.0).any()
    flat = explore.annotate(ds, sec["objectives"], sec["constraints"], within=[])
    assert not (flat["pareto_rank"] == 0).sel(load_torque=80.0).any()  # what grouping prevents
    sampled = {
        "design": "sobol",
        "samples": 8,
        "options": {"driveline": "rigid"},
        "parameters": {
            "ramp_time": {"min": "0.05 s", "max": "0.3 s"},
            "load_torque": {"min": "40 N*m", "max": "80 N*m"},
        },
    }
    sec = resolve({"studies": ["engagement"], "engagement": sampled})["engagement"]
    ds = pipeline.run_study(sec)
    assert ds["pareto_rank"].attrs["conditions_mixed"] == "load_torque"
    assert ds["pareto_rank"].attrs["ranked_within"] == ""


def test_benchmark_runs_small(tmp_path):
    """The benchmark's own check on a small run: equal ranks to the O(N^2) peeling."""
    from clutchlab.bench import pareto as benchmark_pareto

    rows = benchmark_pareto.run(tmp_path, 3000, reference=300)
    assert (
        all(r["equal_to_reference"] for r in rows) and (tmp_path / "pareto_benchmark.csv").exists()
    )
    hv = benchmark_pareto.run_hypervolume(tmp_path, 200)
    assert [r["points"] for r in hv] == [20, 200]
    assert all(r["equal_to_reference"] and r["within_bound"] for r in hv)
    assert (tmp_path / "hypervolume_benchmark.csv").exists()


def test_grid_decomposition_leaves_failed_cells_out():
    """With failed (NaN) cells: means and variances over the finite cells, count-weighted — the
    same numbers as a plain loop over the successful cells — and the count of cells left out."""
    rng = np.random.default_rng(3)
    y = rng.random((4, 3, 5))
    y[1, 2, 0] = y[3, 0, 4] = y[0, 1, 1] = np.nan
    d = explore.grid_variance_decomposition(y, ["a", "b", "c"])
    assert d["failed"] == 3
    cells = [(idx, v) for idx, v in np.ndenumerate(y) if np.isfinite(v)]
    vals = np.array([v for _, v in cells])
    mean, var = vals.mean(), vals.var()
    assert d["variance"] == pytest.approx(var, rel=1e-12)
    for axis, name in enumerate("abc"):
        levels = {}
        groups = {}
        for idx, v in cells:
            levels.setdefault(idx[axis], []).append(v)
            groups.setdefault(idx[:axis] + idx[axis + 1 :], []).append(v)
        main = sum(len(g) * (np.mean(g) - mean) ** 2 for g in levels.values()) / len(vals)
        within = sum(len(g) * np.var(g) for g in groups.values()) / len(vals)
        assert d["first_order"][name] == pytest.approx(main / var, rel=1e-12)
        assert d["total"][name] == pytest.approx(within / var, rel=1e-12)


def test_sensitivity_of_a_factorial_study():
    from clutchlab import pipeline
    from clutchlab.config import resolve

    sec = resolve(
        {
            "studies": ["centrifugal"],
            "centrifugal": {
                "design": "factorial",
                "parameters": {
                    "pressure_angle": {"values": ["25 deg", "38.84 deg", "53 deg", "65 deg"]},
                    "friction_coefficient": {"values": [0.3, 0.4046, 0.5, 0.6]},
                },
            },
        }
    )["centrifugal"]
    ds = pipeline.run_study(sec)
    se = explore.sensitivity(ds, ["reserve_factor", "release_time"])
    assert list(se["output"].values) == ["reserve_factor", "release_time", "failure"]
    assert set(se["factor"].values) == {"pressure_angle", "friction_coefficient"}
    fails = int((ds["status"] != 0).sum())
    assert (
        0 < fails and int(se["failed"].sel(output="failure")) == 0
    )  # the indicator itself never fails
    complete = se.where(se["failed"] == 0, drop=True)  # an exact decomposition: main <= total
    assert (
        "failure" in complete["output"]
        and (complete["first_order"] <= complete["total"] + 1e-12).all()
    )
    for name, var in {**se.coords, **se.data_vars}.items():
        assert "units" in var.attrs and "long_name" in var.attrs, name


def _saltelli_values(fn, n, d, seed=1):
    from clutchlab.doe import saltelli_unit

    return fn(saltelli_unit(n, d, np.random.default_rng(seed)))


def test_sobol_indices_of_the_ishigami_function():
    """Ishigami (a = 7, b = 0.1) on [−π, π]³: S1 = (0.3139, 0.4424, 0), ST = (0.5576, 0.4424,
    0.2437) analytically (Ishigami & Homma 1990; Saltelli et al. 2008 §4.9); each estimate within
    its confidence interval (widened by 10 % for the interval's own sampling error)."""

    def ishigami(u):
        x = -np.pi + 2 * np.pi * u
        return np.sin(x[:, 0]) + 7 * np.sin(x[:, 1]) ** 2 + 0.1 * x[:, 2] ** 4 * np.sin(x[:, 0])

    a, b = 7.0, 0.1
    v = a**2 / 8 + b * np.pi**4 / 5 + b**2 * np.pi**8 / 18 + 0.5
    v1, v2 = 0.5 * (1 + b * np.pi**4 / 5) ** 2, a**2 / 8
    v13 = b**2 * np.pi**8 * (1 / 18 - 1 / 50)
    s1, st_ = np.array([v1, v2, 0]) / v, np.array([v1 + v13, v2, v13]) / v
    r = explore.sobol_indices(_saltelli_values(ishigami, 2**13, 3), 3, ["x1", "x2", "x3"])
    for i, k in enumerate(("x1", "x2", "x3")):
        assert abs(r["first_order"][k] - s1[i]) <= 1.1 * r["first_order_conf"][k] + 1e-3, (k, r)
        assert abs(r["total"][k] - st_[i]) <= 1.1 * r["total_conf"][k] + 1e-3, (k, r)
    assert r["failed"] == 0 and r["blocks_used"] == 2**13


def test_sobol_indices_of_an_additive_function_and_failed_blocks():
    """y = x1 + 2·x2 + 0·x3 (uniform on [0, 1]): S1 = ST = (1/5, 4/5, 0) exactly (no interaction);
    NaN scenarios take their whole block out and are counted."""
    y = _saltelli_values(lambda u: u[:, 0] + 2 * u[:, 1] + 0 * u[:, 2], 2**12, 3)
    y[[5, 17, 18]] = np.nan  # blocks 1, 3 (two in block 3)
    r = explore.sobol_indices(y, 3, ["x1", "x2", "x3"])
    assert r["failed"] == 3 and r["blocks_used"] == 2**12 - 2
    for k, exact in (("x1", 0.2), ("x2", 0.8), ("x3", 0.0)):
        assert abs(r["first_order"][k] - exact) <= 1.1 * r["first_order_conf"][k] + 1e-3
        assert abs(r["total"][k] - exact) <= 1.1 * r["total_conf"][k] + 1e-3
    # the bootstrap intervals are reproducible (SALib draws them unseeded for seed 0: refused)
    assert explore.sobol_indices(y, 3, ["x1", "x2", "x3"]) == r
    with pytest.raises(ValueError, match="seed"):
        explore.sobol_indices(y, 3, ["x1", "x2", "x3"], seed=0)


def test_saltelli_study_sensitivity():
    from clutchlab import pipeline
    from clutchlab.config import resolve

    sec = resolve(
        {
            "studies": ["centrifugal"],
            "centrifugal": {
                "design": "saltelli",
                "samples": 256,
                "parameters": {
                    "pressure_angle": {"min": "25 deg", "max": "55 deg"},
                    "friction_coefficient": {"min": 0.3, "max": 0.5},
                    "spring_force": {"min": "380 N", "max": "480 N"},
                },
            },
        }
    )["centrifugal"]
    ds = pipeline.run_study(sec)
    assert ds.sizes["run"] == 256 * 5
    se = explore.sensitivity(ds, ["reserve_factor", "release_time"])
    outs = se.sel(output=["reserve_factor", "release_time"])
    assert outs["first_order_conf"].notnull().all() and (outs["total"] > 0).all()
    assert se["total"].sel(output="failure").isnull().all() == (int((ds["status"] != 0).sum()) == 0)
    with pytest.raises(ValueError, match="no sensitivity"):
        explore.sensitivity(
            pipeline.run_study(
                resolve(
                    {
                        "studies": ["centrifugal"],
                        "centrifugal": {
                            "design": "lhs",
                            "samples": 8,
                            "parameters": {"spring_force": {"min": "380 N", "max": "480 N"}},
                        },
                    }
                )["centrifugal"]
            ),
            ["reserve_factor"],
        )


def test_pareto_rank_of_a_stored_result_asks_a_new_question():
    """Issue 15 item 6: pareto_rank(ds, objectives) on a study Dataset gives back the stored ranks
    for the stored objectives, and for new objectives the ranks of the array form over the same
    feasible designs and operating conditions."""
    sec, ds = _engagement_over_two_loads()
    again = explore.pareto_rank(ds, sec["objectives"])
    assert again.dims == ds["status"].dims and (again == ds["pareto_rank"]).all()
    new = explore.pareto_rank(ds, ["slip_work:min", "lockup_time:min"])
    f = np.stack([explore.flat(ds, "slip_work"), explore.flat(ds, "lockup_time")], axis=1)
    want = explore.pareto_rank(
        f, explore.flat(ds, "feasible").astype(bool), explore.group_ids(ds, ["load_torque"])
    )
    assert (new.values.reshape(-1) == want).all() and new.attrs["ranked_within"] == "load_torque"


def test_best_compromise_is_the_front_design_nearest_the_ideal_point():
    """Issue 18 item 3: the summary page's best design: on the front, objectives normalised over
    the feasible designs (best 0, worst 1), nearest the origin."""
    import xarray as xr

    f1 = np.array([0.0, 1.0, 2.0, 4.0, 3.0])
    f2 = np.array([4.0, 1.5, 1.0, 0.0, 3.0])  # front: 0, 1, 2, 3; design 4 dominated
    ds = xr.Dataset(
        {
            "a": ("run", f1, {"units": "1", "long_name": "a"}),
            "b": ("run", f2, {"units": "1", "long_name": "b"}),
            "status": ("run", np.zeros(5, np.int8), {"units": "1", "long_name": "status"}),
        }
    )
    ds = explore.annotate(ds, ["a:min", "b:min"], {})
    # normalised: (0, 1), (.25, .375), (.5, .25), (1, 0): nearest the origin is design 1 (0.45)
    assert explore.best_compromise(ds) == 1
    ds2 = explore.annotate(
        ds.assign(status=ds.status.where(ds.run != 1, 4).astype(np.int8)), ["a:min", "b:min"], {}
    )
    assert explore.best_compromise(ds2) == 2
    none = explore.annotate(ds.assign(status=ds.status * 0 + 4), ["a:min", "b:min"], {})
    assert explore.best_compromise(none) is None


def test_a_constraint_margin_is_capacity_over_demand_minus_one():
    """Every margin of clutchlab means the same: capacity over demand minus one, >= 0 where met. A
    constraint on a value against a positive limit gives the study's own margin of that check (the
    roller's contact_stress <= allowable is its contact_stress_margin); on a margin output >= 0,
    that margin; a zero or negative limit keeps the sign right."""
    v = np.array([0.5, 1.0, 2.0, 0.0, -1.0, np.nan])
    np.testing.assert_allclose(
        explore.constraint_margin(v, "max", 1.0), [1.0, 0.0, -0.5, np.inf, np.inf, np.nan]
    )
    np.testing.assert_allclose(
        explore.constraint_margin(v, "min", 2.0), [-0.75, -0.5, 0.0, -1.0, -1.5, np.nan]
    )
    np.testing.assert_allclose(explore.constraint_margin(v, "min", 0.0), v)
    for op in ("max", "min"):
        for limit in (-2.0, 0.0, 1.5):
            m = explore.constraint_margin(v[:5], op, limit)
            met = v[:5] <= limit if op == "max" else v[:5] >= limit
            np.testing.assert_array_equal(m >= 0, met)
    from clutchlab import config, pipeline

    sec = config.resolve(
        {
            "studies": ["roller"],
            "roller": {
                "design": "factorial",
                "parameters": {"rollers": {"values": [6, 8, 12]}},
            },
        }
    )["roller"]
    ds = pipeline.run_study(sec)
    np.testing.assert_allclose(
        ds["constraint_margin"].sel(constraint="contact_stress"),
        ds["contact_stress_margin"],
        rtol=1e-12,
    )
    np.testing.assert_array_equal(
        ds["constraint_margin"].sel(constraint="self_locking_margin"), ds["self_locking_margin"]
    )


@pytest.mark.parametrize(
    "name", ["diaphragm_spring", "engagement", "centrifugal", "sprag", "roller"]
)
def test_every_default_constraint_can_bind(name):
    """Issue 30 item 9: the roller's default constraint self_locking_margin >= 0 could never bind
    (the output was the ratio mu/tan(alpha/2), locking above 1). Over the default study's design
    (config/config.yaml), every default constraint of every study is violated by some design and
    met by another, on designs whose output is a number."""
    from pathlib import Path

    from clutchlab import config, pipeline, studies

    sec = config.load(Path(__file__).parents[1] / "config" / "config.yaml")[name]
    default = studies.get(name).constraints
    assert {k: tuple(v) for k, v in sec["constraints"].items()} == dict(default)
    ds = pipeline.run_study(sec)
    for output in sec["constraints"]:
        m = ds["constraint_margin"].sel(constraint=output).values
        assert (m < 0).any() and (m >= 0).any(), output


@pytest.mark.parametrize(
    "a",
    [
        np.random.default_rng(1).integers(0, 4, (5000, 3)).astype(float),
        np.c_[
            np.random.default_rng(2).choice([1.0, np.inf, -np.inf, -0.0, 0.0, 2.5], 5000),
            np.random.default_rng(3).integers(0, 3, 5000),
        ],
        np.random.default_rng(4).random((3000, 2)),  # every row distinct
        np.random.default_rng(5).integers(-3, 3, (400, 2)),  # integers
        np.zeros((0, 2)),
        np.array([[1.0, np.nan], [1.0, np.nan], [0.0, 1.0]]),  # NaN: numpy's answer
    ],
)
def test_unique_rows_is_numpys_unique_along_rows(a):
    rows, inverse = explore.unique_rows(a, return_inverse=True)
    rows0, inverse0 = np.unique(a, axis=0, return_inverse=True)
    assert rows.dtype == rows0.dtype
    np.testing.assert_array_equal(rows, rows0)
    np.testing.assert_array_equal(np.ravel(inverse), np.ravel(inverse0))


def test_flat_broadcasts_like_xarray():
    ds = xr.Dataset(
        {
            "status": (("a", "b"), np.zeros((3, 4), np.int8)),
            "x": (("b", "a"), np.arange(12.0).reshape(4, 3)),
            "y": ("a", [1.0, 2.0, 3.0]),
            "z": ((), 7.0),
        },
        coords={"b": [10, 20, 30, 40]},
    )
    for name in ("x", "y", "z", "b", "status"):
        expected = ds[name].broadcast_like(ds["status"]).transpose("a", "b").values.reshape(-1)
        got = explore.flat(ds, name)
        np.testing.assert_array_equal(got, expected)
        got[:] = 0  # a new array: the Dataset is untouched
    assert ds["x"].values.sum() == 66.0


def _tiny_result():
    """A 2 × 2 grid of scenarios with two outputs (SI) and statuses, as a study stores it."""
    return xr.Dataset(
        {
            "status": (("a", "b"), np.zeros((2, 2), dtype=st.DTYPE)),
            "slip_work": (("a", "b"), [[5e3, 6e3], [7e3, 8e3]], {"units": "J"}),
            "lockup_time": (("a", "b"), [[0.4, 0.3], [0.2, 0.1]], {"units": "s"}),
        },
        coords={"a": [1.0, 2.0], "b": [3.0, 4.0]},
    )


@pytest.mark.parametrize(
    "constraints",
    [
        {"slip_work": ("<=", 6e3)},
        {"slip_work": ("maximum", 6e3)},
        {"slip_work": ("MAX", 6e3)},
        {"slip_work": ("max", "6 kJ")},
        {"slip_work": ("max", np.nan)},
        {"slip_work": ("max", True)},
        {"slip_wrk": ("max", 6e3)},
        {"slip_work": "max"},
    ],
)
def test_a_constraint_that_is_not_one_is_refused_naming_it(constraints):
    """explore.feasible read any operator but "max" as a minimum ("<=" gave the opposite answer)
    and failed on a limit written with its unit with a TypeError."""
    with pytest.raises(ValueError, match="slip_w"):
        explore.feasible(_tiny_result(), constraints)
    ok, _ = explore.feasible(_tiny_result(), {"slip_work": ("max", 6e3)})
    assert ok.tolist() == [[True, True], [False, False]]


@pytest.mark.parametrize("objective", ["slip_work:MIN", "slip_work:minimum", "slip_work", "x:min"])
def test_an_objective_that_is_not_one_is_refused_naming_it(objective):
    """A typo in an objective's sense ranked it maximised (any sense but "min")."""
    with pytest.raises(ValueError, match="objective"):
        explore.annotate(_tiny_result(), [objective, "lockup_time:min"], {})
