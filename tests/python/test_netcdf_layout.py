"""Result files laid out for netCDF tools: xarray/h5netcdf open a group on its own with
real coordinates (no phony dimensions), every dataset carries long_name (and units where
its name has one), data are chunked and compressed with HDF5's filters, and the values
are exactly the recorded ones."""
from __future__ import annotations

import subprocess

import h5py
import numpy as np
import pytest

import packsim
from h5_tree import datasets as h5_datasets

xr = pytest.importorskip("xarray")
pytest.importorskip("h5netcdf")

# A fault scenario: it records /hardware and per-device monitor readings too.
SCENARIO = "a_host_dead"

# The unit a dataset's name promises (STYLE: units in names) -> its `units` attribute.
SUFFIX_UNITS = {"_s": "s", "_V": "V", "_A": "A", "_W": "W", "_C": "degC", "_mV": "mV", "_mA": "mA"}


@pytest.fixture(scope="module")
def written(cli, tmp_path_factory):
    out = tmp_path_factory.mktemp("nc") / "run.h5"
    subprocess.run([str(cli), "run", SCENARIO, "-o", str(out), "-q"], check=True)
    return out


def _datasets(path):
    with h5py.File(path, "r") as f:
        return {k: (v.shape, v.compression, v.shuffle, v.chunks, dict(v.attrs)) for k, v in h5_datasets(f)}


def test_each_group_opens_in_xarray_on_real_coordinates(written):
    r = packsim.load(written)
    groups = sorted({k.split("/")[0] for k in r.keys() if "/" in k})
    assert {"truth", "measured", "bms", "hardware"} <= set(groups)
    for g in groups:
        ds = xr.open_dataset(written, engine="h5netcdf", group=g)
        try:
            assert not [d for d in ds.dims if str(d).startswith("phony_dim")], (g, dict(ds.sizes))
            np.testing.assert_array_equal(ds["time_s"].values, r.time_s)
            names = [k.split("/", 1)[1] for k in r.keys() if k.startswith(g + "/")]
            assert set(names) == set(ds.data_vars), g
            for name in names:
                v = ds[name]
                assert v.dims[0] == "time_s", (g, name, v.dims)
                np.testing.assert_array_equal(v.values, r[f"{g}/{name}"])
        finally:
            ds.close()
    with xr.open_dataset(written, engine="h5netcdf", group="truth") as truth:
        assert truth["cell_voltage_V"].dims == ("time_s", "cell")
        np.testing.assert_array_equal(truth["cell"].values, np.arange(1, r.n_cells + 1))
        assert truth["cell_voltage_V"].attrs["units"] == "V" and truth["cell_voltage_V"].attrs["long_name"]
    with xr.open_dataset(written, engine="h5netcdf", group="measured") as m:
        assert m["cell_voltage_mV"].dims == ("time_s", "series")
        assert m["temperature_dC"].dims == ("time_s", "thermistor") and m.sizes["thermistor"] == r.n_thermistors
    with xr.open_dataset(written, engine="h5netcdf", group="bms") as b:
        assert b["comm_bad"].dims == ("time_s", "device")


def test_root_opens_too_with_the_events_on_their_own_dimension(written):
    with xr.open_dataset(written, engine="h5netcdf") as root:
        assert not [d for d in root.dims if str(d).startswith("phony_dim")], dict(root.sizes)
        assert root["events"].dims == ("event",) and root.sizes["event"] == len(packsim.load(written).events)


def test_every_dataset_has_long_name_units_chunks_and_compression(written):
    info = _datasets(written)
    for path, (shape, compression, shuffle, chunks, attrs) in info.items():
        if attrs.get("CLASS") == b"DIMENSION_SCALE" and path != "time_s":
            continue
        assert isinstance(attrs.get("long_name"), (str, bytes)) and attrs["long_name"], path
        for suffix, unit in SUFFIX_UNITS.items():
            if path.endswith(suffix):
                units = attrs.get("units")
                units = units.decode() if isinstance(units, bytes) else units
                assert units == unit, (path, units)
        if path != "events" and np.prod(shape) > 0:
            assert compression == "gzip" and shuffle and chunks is not None, path


def test_values_are_the_recorded_ones_bit_for_bit(written):
    # packsim.run's arrays view the C++ recording directly (no file in between); the file
    # holds them bit for bit, but float channels with a `resolution` attribute, which it
    # keeps to half that step.
    f = packsim.load(written)
    r = packsim.run(SCENARIO)
    with h5py.File(written) as h:
        resolution = {k: h[k].attrs["resolution"] for k in r.keys() if "resolution" in h[k].attrs}
    for k in r.keys():
        assert f[k].dtype == r[k].dtype and f[k].shape == r[k].shape, k
        if k in resolution:
            assert np.abs(f[k] - r[k]).max() <= 0.5 * resolution[k] * (1 + 1e-6), k
        elif f[k].dtype.names is None:
            assert f[k].tobytes() == r[k].tobytes(), k
    assert f.events == r.events and f.summary == r.summary


def test_run_reads_nothing_from_disk(monkeypatch):
    # packsim.run builds its file in memory: no temporary file is created.
    import tempfile
    def no_temp(*a, **k):
        raise AssertionError("packsim.run created a temporary file")
    monkeypatch.setattr(tempfile, "mkdtemp", no_temp)
    monkeypatch.setattr(tempfile, "mkstemp", no_temp)
    monkeypatch.setattr(tempfile, "NamedTemporaryFile", no_temp)
    r = packsim.run("bench_6s_ncr18650_2C")
    assert r.events is not None and r.summary["duration_s"] > 0 and r.source is None


def test_run_keeps_a_scenario_text_beyond_64_kib(simple_yaml):
    # Attributes that large need HDF5's dense attribute storage (the 1.8 file format the
    # writer asks for), in the file packsim.run builds in memory as in the CLI's.
    n = 9000
    times = ", ".join(str(0.1 * k) for k in range(n))
    currents = ", ".join("2.0" if k % 2 else "1.5" for k in range(n))
    text = simple_yaml.replace("load: {current_A: 2.0}\nrun: {duration_s: 600}\n",
                               f"load:\n  points:\n    time_s: [{times}]\n    current_A: [{currents}]\n")
    assert len(text) > 64 * 1024
    r = packsim.run(text)
    assert r.scenario_yaml == text and r.n_samples > 100
