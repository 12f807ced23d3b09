"""HDF5 store: metadata contract, atomic writes, compression, round trip."""
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from clutchlab import doe, store
from clutchlab.config import resolve


@pytest.fixture(scope="module")
def result():
    sec = resolve({"studies": ["diaphragm_spring"], "diaphragm_spring": {
        "design": "factorial", "parameters": {"sheet_thickness": {"values": ["2 mm", "2.5 mm"]},
                                              "cone_height_ratio": {"values": [1.3, 1.6, 1.9]}}}})["diaphragm_spring"]
    return doe.run_study(sec)


def test_every_variable_has_units_and_long_name(result):
    for name, var in {**result.coords, **result.data_vars}.items():
        assert "units" in var.attrs and "long_name" in var.attrs, name


def test_status_is_cf_flag(result):
    s = result["status"]
    assert s.dtype == np.int8
    assert len(np.atleast_1d(s.attrs["flag_values"])) == len(s.attrs["flag_meanings"].split())
    assert set(store.flag_meanings(result).values.ravel()) <= {"ok", "monotone_no_hump"}


def test_provenance(result):
    for key in ("clutchlab_version", "study", "config", "model", "design"):
        assert result.attrs[key]


def test_roundtrip(tmp_path, result):
    path = store.write(result, tmp_path / "a" / "r.h5")
    xr.testing.assert_identical(store.load(path), result)
    import h5py

    with h5py.File(path) as f:
        assert f["curve_load"].compression == "gzip"


def test_missing_metadata_refused(tmp_path):
    ds = xr.Dataset({"x": ("a", np.arange(3.0), {"units": "m"})})
    with pytest.raises(store.MissingMetadata, match="x \\(long_name\\)"):
        store.write(ds, tmp_path / "x.h5")
    assert not list(tmp_path.iterdir())


def test_failed_write_leaves_no_file(tmp_path, result, monkeypatch):
    target = tmp_path / "r.h5"
    store.write(result, target)
    before = target.read_bytes()

    def boom(self, path, **kw):
        Path(path).write_bytes(b"partial")
        raise KeyboardInterrupt

    monkeypatch.setattr(xr.Dataset, "to_netcdf", boom)
    with pytest.raises(KeyboardInterrupt):
        store.write(result, target)
    assert target.read_bytes() == before  # old complete file untouched
    assert [p.name for p in tmp_path.iterdir()] == ["r.h5"]  # no temporary left behind


def test_same_input_same_bytes(tmp_path, result):
    a = store.write(result, tmp_path / "a.h5").read_bytes()
    b = store.write(result, tmp_path / "b.h5").read_bytes()
    assert a == b
