"""Issue 15 item 4: refinement towards the Pareto front (design kind 'refine') and the hypervolume
that shows how far a front moved."""

import itertools
from pathlib import Path

import numpy as np
import pytest
import yaml

from clutchlab import config, doe, explore, pipeline, store, studies
from clutchlab.config import ConfigError

ROOT = Path(__file__).resolve().parents[1]


def _cells(points, ref):
    """Hypervolume of integer points by counting the unit cells they dominate (exact)."""
    m = len(ref)
    count = 0
    for cell in itertools.product(*(range(int(r)) for r in ref)):
        if any(all(p[k] <= cell[k] for k in range(m)) for p in points):
            count += 1
    return count


@pytest.mark.parametrize("m", [1, 2, 3, 4])
def test_hypervolume_equals_cell_count(m):
    """Exact hypervolume against counting dominated unit cells, with duplicates, dominated points
    and points outside the reference box among random integer points."""
    rng = np.random.default_rng(m)
    ref = np.full(m, 6.0)
    for _ in range(20):
        p = rng.integers(0, 8, size=(rng.integers(1, 12), m)).astype(float)
        assert explore.hypervolume(p, ref) == _cells(p, ref)


def test_hypervolume_of_known_fronts():
    assert explore.hypervolume([[1, 3], [2, 2], [3, 1]], [4, 4]) == 6.0  # 1x1 + 1x2 + 1x3
    assert explore.hypervolume([[0.5, 0.5, 0.5]], [1, 1, 1]) == pytest.approx(0.125)
    assert explore.hypervolume([[5, 5]], [4, 4]) == 0.0  # beyond the reference: nothing
    assert explore.hypervolume(np.empty((0, 2)), [1, 1]) == 0.0
    # a non-finite point (a failed design) is refused, not dropped: the volume would look valid
    with pytest.raises(ValueError, match="1 of 2 points have a non-finite objective"):
        explore.hypervolume([[np.nan, 0.0], [0.5, 0.5]], [1, 1])
    assert explore.hypervolume([[0.5, 0.5]], [1, 1]) == pytest.approx(0.25)


def _first_stage(folder: Path, section: dict | None = None) -> Path:
    """A stored engagement result (a small factorial grid over a design factor and a load) at the
    path config/refine.yaml refines: <folder>/results/engagement/engagement.h5."""
    section = section or {
        "design": "factorial",
        "options": {"driveline": "rigid"},
        "parameters": {
            "ramp_time": {"values": ["0.05 s", "0.15 s", "0.3 s"]},
            "sheet_thickness": {"values": ["2.1 mm", "2.6 mm"]},
            "load_torque": {"values": ["44 N*m", "80 N*m"]},
        },
    }
    sec = config.resolve({"studies": ["engagement"], "engagement": section})["engagement"]
    path = folder / "results" / studies.get("engagement").output
    path.parent.mkdir(parents=True, exist_ok=True)
    store.write(pipeline.run_study(sec), path)
    return path


def _refine(path, results="refined", **extra):
    section = {"design": "refine", "refine": {"from": str(path)}, "samples": 12, "seed": 3, **extra}
    return {
        "studies": ["engagement"],
        "results": str(Path(path).parents[2] / results),
        "engagement": section,
    }


def test_refine_takes_everything_but_the_samples_from_the_stored_result(tmp_path):
    path = _first_stage(tmp_path)
    sec = config.resolve(_refine(path))["engagement"]
    stored = yaml.safe_load(store.load(path).attrs["config"])
    for key in ("factors", "fixed", "options", "objectives", "constraints"):
        assert sec[key] == stored[key], key
    assert sec["design"] == "refine" and sec["samples"] == 12 and sec["refine"]["shrink"] == 0.5


@pytest.mark.parametrize(
    "change, key",
    [
        (
            lambda cfg, p: cfg["engagement"]["refine"].update({"from": str(p.parent / "none.h5")}),
            "engagement.refine.from",
        ),
        (
            lambda cfg, p: cfg.update({"results": str(p.parents[1])}),
            "engagement.refine.from",
        ),  # its own output
        (
            lambda cfg, p: cfg["engagement"].update({"parameters": {"ramp_time": "0.1 s"}}),
            "engagement.parameters",
        ),
        (
            lambda cfg, p: cfg["engagement"].update({"objectives": ["slip_work:min"]}),
            "engagement.objectives",
        ),
        (lambda cfg, p: cfg["engagement"].pop("samples"), "engagement.samples"),
        (
            lambda cfg, p: cfg["engagement"]["refine"].update({"shrink": 0}),
            "engagement.refine.shrink",
        ),
        (
            lambda cfg, p: cfg["engagement"]["refine"].update({"shrink": 1.5}),
            "engagement.refine.shrink",
        ),
        (lambda cfg, p: cfg.update({"results": "my results"}), "results"),
    ],
)
def test_refine_config_refusals(tmp_path, change, key):
    path = _first_stage(tmp_path)
    cfg = _refine(path)
    change(cfg, path)
    with pytest.raises(ConfigError) as exc:
        config.resolve(cfg)
    assert str(exc.value).startswith(f"config key '{key}'"), str(exc.value)


def test_refine_refuses_another_studys_result_and_a_factorial_refine_key(tmp_path):
    sec = config.resolve(
        {
            "studies": ["centrifugal"],
            "centrifugal": {
                "design": "factorial",
                "parameters": {"pressure_angle": {"values": ["30 deg", "40 deg"]}},
            },
        }
    )["centrifugal"]
    other = tmp_path / "centrifugal.h5"
    store.write(pipeline.run_study(sec), other)
    with pytest.raises(ConfigError, match="result of study 'centrifugal'"):
        config.resolve(_refine(other))
    with pytest.raises(ConfigError) as exc:
        config.resolve(
            {
                "studies": ["engagement"],
                "engagement": {"design": "factorial", "refine": {"from": str(other)}},
            }
        )
    assert str(exc.value).startswith("config key 'engagement.refine'")


def test_refined_samples_stay_in_the_boxes_of_the_front(tmp_path):
    """Each new design lies within ±h (h = shrink x the grid step, in the factor's range) of a front
    design of the first stage that shares its operating condition; conditions stay at grid values;
    the same seed gives the same design."""
    path = _first_stage(tmp_path)
    first = store.load(path)
    sec = config.resolve(_refine(path, samples=40))["engagement"]
    ds = doe.build_design(sec)
    assert ds.attrs["refine_within"] == "load_torque"
    assert ds["ramp_time"].attrs["refine_halfwidth"] == pytest.approx(
        0.5 * 0.5
    )  # 3 levels: step 1/2
    assert ds["sheet_thickness"].attrs["refine_halfwidth"] == pytest.approx(0.5 * 1.0)  # 2 levels
    assert ds["load_torque"].attrs["refine_halfwidth"] == 0.0
    assert set(np.unique(ds["load_torque"].values)) <= {44.0, 80.0}
    import pandas as pd

    on = explore.flat(first, "pareto_rank") == 0
    front = pd.DataFrame(
        {k: explore.flat(first, k)[on] for k in ("ramp_time", "sheet_thickness", "load_torque")}
    )
    span = {"ramp_time": 0.25, "sheet_thickness": 0.5e-3}
    for i in range(ds.sizes["run"]):
        x = {k: float(ds[k].values[i]) for k in ("ramp_time", "sheet_thickness", "load_torque")}
        assert 0.05 <= x["ramp_time"] <= 0.3 and 2.1e-3 <= x["sheet_thickness"] <= 2.6e-3
        near = front[
            (front.load_torque == x["load_torque"])
            & ((front.ramp_time - x["ramp_time"]).abs() <= 0.5 * span["ramp_time"] + 1e-12)
            & (
                (front.sheet_thickness - x["sheet_thickness"]).abs()
                <= 1.0 * span["sheet_thickness"] + 1e-12
            )
        ]
        assert len(near), x
    again = doe.build_design(sec)
    assert all(
        np.array_equal(again[k].values, ds[k].values) for k in ("ramp_time", "sheet_thickness")
    )


def test_refinement_moves_the_engagement_front_with_fewer_scenarios(tmp_path):
    """Acceptance of issue 15: the default study's engagement grid (120 scenarios, compliant
    driveline, config/config.yaml), refined with 60 new scenarios (config/refine.yaml's design):
    the hypervolume of every operating condition's front grows. (The default study is robust, its
    grid crossed with the friction's scatter: refining a robust study is tested in
    tests/test_robust.py; here the grid alone, each condition's own front.)"""
    raw = yaml.safe_load((ROOT / "config" / "config.yaml").read_text())["engagement"]
    from conftest import without_robust

    raw = without_robust(raw)
    path = _first_stage(tmp_path, raw)
    refine = yaml.safe_load((ROOT / "config" / "refine.yaml").read_text())["engagement"]
    refine["refine"]["from"] = str(path)
    sec = config.resolve(
        {"studies": ["engagement"], "results": str(tmp_path / "refined"), "engagement": refine}
    )["engagement"]
    first, second = store.load(path), pipeline.run_study(sec)
    assert second.sizes["run"] < first["status"].size
    gain = explore.refinement_gain(first, second)
    assert gain.sizes["group"] == 4  # 2 load torques x 2 driven inertias
    assert (gain["hypervolume_after"] > gain["hypervolume_before"]).all()
    assert (gain["front_from_second"] > 0).all()
    # a second refinement of the refined result halves the boxes again
    second_path = tmp_path / "refined" / studies.get("engagement").output
    second_path.parent.mkdir(parents=True)
    store.write(second, second_path)
    third = config.resolve(_refine(second_path, results="third"))["engagement"]
    ds = doe.build_design(third)
    assert ds["ramp_time"].attrs["refine_halfwidth"] == pytest.approx(
        0.5 * second["ramp_time"].attrs["refine_halfwidth"]
    )


def test_refine_refuses_a_first_stage_value_todays_checks_refuse(tmp_path):
    """A result made before a check was added (here: a cushion travel of 0.6 m, a bare 0.6 meant
    in mm) is refused when the refinement is configured, naming it, not run into scenarios of
    status invalid_input; a first stage's own plausible range is the one its values are held to."""
    import h5py

    path = _first_stage(tmp_path)
    with h5py.File(path, "r+") as fh:
        section = yaml.safe_load(fh.attrs["config"])
        section["fixed"]["cushion_travel"] = 0.6
        fh.attrs["config"] = yaml.safe_dump(section)
    with pytest.raises(ConfigError) as exc:
        config.resolve(_refine(path))
    assert exc.value.key == "engagement.refine.from"
    assert "first stage's cushion_travel" in str(exc.value) and "0.6 m" in str(exc.value)
    with h5py.File(path, "r+") as fh:
        section["options"]["plausible"] = {"cushion_travel": [1e-7, 1.0]}
        fh.attrs["config"] = yaml.safe_dump(section)
    sec = config.resolve(_refine(path))["engagement"]
    assert sec["options"]["plausible"] == {"cushion_travel": [1e-7, 1.0]}
