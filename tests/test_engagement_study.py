"""The engagement study: spring design -> clamp force -> capacity -> engagement."""
from pathlib import Path

import numpy as np
import pytest

from clutchlab import config, doe, report, store
from clutchlab import status as st

ROOT = Path(__file__).resolve().parents[1]


def _study(options, **params):
    return config.resolve({"studies": ["engagement"], "engagement": {
        "design": "factorial", "options": options, "parameters": params}})["engagement"]


def test_seed000_through_the_whole_chain():
    """Seed spring (F_B = 2500 N) -> eq. (14) as printed (239.3 N m) -> rigid closed form, held engine:
    lock-up 0.150 s (tol 1 %) and slip work 5800 J (tol 2 %), seed 000 sections 5.2-5.3."""
    sec = _study({"driveline": "rigid", "capacity_formula": "eq14_as_printed"}, cone_height_ratio=3.5 / 2.334,
                 stack_mass="4.757 kg", engine_inertia="inf")
    ds = doe.run_study(sec)
    assert ds.attrs["model_used"] == "rigid two-inertia, closed form"
    assert float(ds["peak_capacity"]) == pytest.approx(239.3, rel=2e-3)
    assert float(ds["lockup_time"]) == pytest.approx(0.150, rel=0.01)
    assert float(ds["slip_work"]) == pytest.approx(5800.0, rel=0.02)


def test_default_study_energy_and_metadata(tmp_path):
    """Acceptance: energy_residual <= 1e-9 relative for every scenario of the default study."""
    sec = config.load(ROOT / "config" / "config.yaml")["engagement"]
    ds = doe.run_study(sec)
    ok = ds["status"] == st.CODE["ok"]
    assert int(ok.sum()) > 0.8 * ok.size
    assert float(np.abs(ds["energy_residual"]).max()) <= 1e-9
    assert bool((ds["peak_jerk"].values[ok.values] > 0).all())
    path = store.write(ds, tmp_path / "engagement.h5")  # checks units and long_name everywhere
    written = report.build({"engagement": path}, [], tmp_path / "report")
    assert {p.stem for p in written} >= {"engagement_tradeoff", "engagement_maps"}


def test_infinite_only_where_allowed():
    with pytest.raises(config.ConfigError, match="driven_inertia"):
        _study({}, driven_inertia="inf")
