"""HDF5 store: metadata contract, atomic writes, compression, round trip."""

from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from clutchlab import doe, pipeline, store
from clutchlab.config import resolve


@pytest.fixture(scope="module")
def result():
    sec = resolve(
        {
            "studies": ["diaphragm_spring"],
            "diaphragm_spring": {
                "design": "factorial",
                "parameters": {
                    "sheet_thickness": {"values": ["2 mm", "2.5 mm"]},
                    "cone_height_ratio": {"values": [1.3, 1.6, 1.9]},
                },
            },
        }
    )["diaphragm_spring"]
    return pipeline.run_study(sec)


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
        assert (
            f["curve_load"].compression is None and f["curve_load"].chunks is None
        )  # floats: contiguous


def test_filters_per_dtype_not_inherited(tmp_path):
    """Floats contiguous and uncompressed, integers gzip + shuffle (store._encoding); a variable
    loaded from a file does not bring that file's filters; complevel 0 compresses nothing."""
    import h5py

    ds = xr.Dataset(
        {
            "x": ("run", np.linspace(0, 1, 500), {"units": "m", "long_name": "x"}),
            "status": ("run", np.zeros(500, np.int8), {"units": "1", "long_name": "status"}),
        }
    )
    ds["x"].encoding.update(
        compression="gzip", compression_opts=9, chunksizes=(10,)
    )  # as if loaded
    a = store.write(ds, tmp_path / "a.h5")
    b = store.write(store.load(a), tmp_path / "b.h5")
    c = store.write(store.load(a), tmp_path / "c.h5", complevel=0)
    for path in (a, b):
        with h5py.File(path) as f:
            assert f["x"].compression is None and f["x"].chunks is None
            assert f["status"].compression == "gzip" and f["status"].shuffle
    with h5py.File(c) as f:
        assert f["status"].compression is None and f["x"].compression is None
    assert ds["x"].encoding["compression"] == "gzip"  # the caller's Dataset is not changed
    xr.testing.assert_identical(store.load(c), store.load(a))


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


def test_files_follow_the_umask(result, tmp_path):
    import os

    old = os.umask(0o022)
    try:
        p = store.write(result, tmp_path / "a.h5")
        assert p.stat().st_mode & 0o777 == 0o644
        os.umask(0o027)
        p = store.write(result, tmp_path / "b.h5")
        assert p.stat().st_mode & 0o777 == 0o640
    finally:
        os.umask(old)


def test_stale_temporaries_of_a_dead_process_are_removed(result, tmp_path):
    import socket
    import subprocess
    import sys

    dead = subprocess.run(
        [sys.executable, "-c", "import os; print(os.getpid())"], capture_output=True, text=True
    ).stdout.strip()
    stale = tmp_path / f".r.h5.{socket.gethostname()}.{dead}.deadbeef.tmp"
    stale.write_bytes(b"x" * 1000)
    other_host = tmp_path / ".r.h5.elsewhere.1.cafe0000.tmp"  # another host's writer may still run
    other_host.write_bytes(b"x")
    store.write(result, tmp_path / "r.h5")
    assert not stale.exists() and other_host.exists()
    assert sorted(p.name for p in tmp_path.iterdir()) == [other_host.name, "r.h5"]


def test_a_failed_write_leaves_nothing(result, tmp_path):
    with pytest.raises(ZeroDivisionError):
        with store.atomic(tmp_path / "x.png") as tmp:
            tmp.write_bytes(b"half")
            raise ZeroDivisionError  # a crash while the file is open
    assert list(tmp_path.iterdir()) == []


@pytest.fixture
def chunk(tmp_path):
    sec = resolve(
        {
            "studies": ["roller"],
            "roller": {
                "design": "factorial",
                "parameters": {
                    "rollers": {"values": [8, 12]},
                    "wedge_angle": {"values": ["9 deg", "11 deg"]},
                },
            },
        }
    )["roller"]
    design = doe.build_design(sec)
    return store.write(
        pipeline.run_chunk(design, sec["options"], 1, 0),
        tmp_path / "chunk_0000.h5",
        with_checksum=True,
    )


def test_a_chunk_reads_back_against_its_checksum(chunk):
    ds = store.load_verified(chunk)
    assert "clutchlab_checksum" not in ds.attrs and ds.sizes["run"] == 4


def test_a_changed_chunk_is_named_and_removed(chunk):
    import h5py

    with h5py.File(chunk, "r+") as f:
        f["contact_stress"][1] = f["contact_stress"][1] * 1.001
    with pytest.raises(store.CorruptChunk, match="chunk_0000.h5 does not match its checksum"):
        store.load_verified(chunk)
    assert not chunk.exists()  # the next snakemake run recomputes it


def test_a_truncated_chunk_is_named_and_removed(chunk):
    data = chunk.read_bytes()
    chunk.write_bytes(data[: len(data) // 2])
    with pytest.raises(store.CorruptChunk, match="chunk_0000.h5 cannot be read"):
        store.load_verified(chunk)
    assert not chunk.exists()


def _edits(ds: xr.Dataset) -> dict:
    """One small change of each kind the checksum must see."""
    first = ds.copy(deep=True)
    first["clamp_load"].values[0, 0] = np.nextafter(first["clamp_load"].values[0, 0], np.inf)
    units = ds.copy(deep=True)
    units["clamp_load"].attrs["units"] = "kN"
    extra = ds.copy(deep=True)
    extra["clamp_load"].attrs["comment"] = "edited"
    glob = ds.copy(deep=True)
    glob.attrs["config"] = glob.attrs["config"].replace("206000000000.0", "200000000000.0")
    thickness = ds["sheet_thickness"]
    coord = ds.assign_coords(sheet_thickness=thickness.copy(data=thickness.values + [1e-6, 0.0]))
    renamed = ds.rename({"clamp_load": "clamp_force"})
    dropped = ds.drop_vars("reserve_factor")
    as_coord = ds.set_coords("reserve_factor")
    return {
        "a value by one ulp": first,
        "a unit": units,
        "a new attribute": extra,
        "a global attribute": glob,
        "a coordinate value": coord,
        "a variable's name": renamed,
        "a variable removed": dropped,
        "a data variable made a coordinate": as_coord,
    }


def test_the_checksum_covers_values_and_attributes(result):
    """Item 8: the checksum used to cover values only (a unit edited in a chunk was carried into
    the result); it covers every variable's values, attributes, name and role, and the global
    attributes but the checksum's own. It does not depend on how a NaN is spelled in memory, on a
    scalar attribute stored as a one-element list, or on the checksum attributes themselves."""
    base = store.checksum(result)
    digests = {what: store.checksum(ds) for what, ds in _edits(result).items()}
    assert base not in digests.values()
    assert len(set(digests.values())) == len(digests)
    neg_nan = result.copy(deep=True)
    values = neg_nan["load_peak"].values  # NaN where the spring has no hump (H/h = 1.3)
    assert np.isnan(values).any()
    values[...] = np.where(np.isnan(values), -np.nan, values)  # another NaN bit pattern
    assert np.signbit(values[np.isnan(values)]).all()
    one = result.copy(deep=True)
    one["clamp_load"].attrs["scale"] = [2.0]
    scalar = result.copy(deep=True)
    scalar["clamp_load"].attrs["scale"] = 2.0
    assert store.checksum(neg_nan) == base
    assert store.checksum(one) == store.checksum(scalar) != base
    assert store.checksum(result.assign_attrs(store.checksum_attrs(result))) == base


def test_a_stored_file_is_hashed_block_by_block_as_in_memory(result, tmp_path, monkeypatch):
    """The checksum of a file read lazily a block of rows at a time (blocks far smaller than a
    variable here) is the in-memory one; a change is named by variable."""
    import h5py

    path = store.write(result, tmp_path / "r.h5", with_checksum=True)
    monkeypatch.setattr(store, "BLOCK_VALUES", 5)
    assert store.seal(path) == store.checksum(result)
    assert store.file_checksum_problem(path) is None
    with h5py.File(path, "r+") as f:
        f["clamp_load"].attrs["units"] = "kN"
        f["reserve_factor"][1, 2] = 0.5
        f.attrs["title"] = "edited"
    assert store.file_checksum_problem(path) == (
        "does not match its checksum (changed after it was written: clamp_load attributes, "
        "reserve_factor values)"
    )
    with h5py.File(path, "r+") as f:
        f["clamp_load"].attrs["units"] = "N"
        f["reserve_factor"][1, 2] = result["reserve_factor"].values[1, 2]
    assert store.file_checksum_problem(path) == (
        "does not match its checksum (changed after it was written: global attributes)"
    )


def test_a_chunk_with_an_edited_attribute_is_named_and_removed(chunk):
    """Item 8: a unit attribute edited in a chunk is found like a changed value."""
    import h5py

    with h5py.File(chunk, "r+") as f:
        f["contact_stress"].attrs["units"] = "MPa"
    with pytest.raises(
        store.CorruptChunk,
        match=r"chunk_0000.h5 does not match its checksum \(changed after it was written: "
        r"contact_stress attributes\); it has been removed",
    ):
        store.load_verified(chunk)
    assert not chunk.exists()


def test_a_missing_chunk_is_named(tmp_path):
    with pytest.raises(store.CorruptChunk, match="chunk_0003.h5 does not exist; run snakemake"):
        store.load_verified(tmp_path / "chunk_0003.h5")
    assert store.file_checksum_problem(tmp_path / "chunk_0003.h5") == "does not exist"
