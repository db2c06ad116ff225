"""run -> save -> load gives the very same datasets, and the in-memory Result of
packsim.run has exactly the layout of the file the C++ writer produces."""
from __future__ import annotations

import numpy as np
import pytest

import packsim
from stored import assert_as_stored, same_bits as _same


def test_run_save_load_identical(race, tmp_path):
    """Every dataset the same, but for float channels stored to a stated `resolution`
    (docs/results.md): those within half of it; a file loaded and saved again is then
    the same bit for bit."""
    path = tmp_path / "race.h5"
    race.save(path)
    back = packsim.load(path)
    assert "resolution" in back.attrs["truth/cell_voltage_V"]
    assert_as_stored(back, race)
    again = tmp_path / "again.h5"
    back.save(again)
    twice = packsim.load(again)
    for k in back.keys():
        assert _same(back[k], twice[k]), k
    assert back.attrs == race.attrs
    assert back.summary == race.summary
    assert back.events == race.events
    assert back.scenario_yaml == race.scenario_yaml
    assert back.seed == race.seed == 42


def test_layout_is_the_documented_one(race):
    n, cells = race.n_samples, race.n_cells
    assert n > 100 and cells == 12
    for k in ("truth/cell_voltage_V", "truth/cell_current_A", "truth/cell_soc", "truth/cell_temp_C"):
        assert race[k].shape == (n, cells) and race[k].dtype == np.float64
    assert race["measured/cell_voltage_mV"].dtype == np.uint16
    assert race["measured/temperature_dC"].shape == (n, 5)  # four pack thermistors, one on the balancing board
    assert race["bms/fault_latched"].dtype == np.uint32
    assert race.units("truth/cell_voltage_V") == "V"
    assert "overcurrent_discharge" in race.fault_names or len(race.fault_names) >= 5
    ev = race.events
    assert ev and {"time_s", "kind", "detail"} <= set(ev[0]) and isinstance(ev[0]["kind"], str)
    assert ev[-1]["kind"] == "run"
    assert set(race.truth) >= {"cell_voltage_V", "pack_current_A"}
    np.testing.assert_array_equal(race.time_s, race["time_s"])


def test_recorded_arrays_are_readonly_views_without_copy(race):
    a = race["truth/cell_voltage_V"]
    assert not a.flags.writeable
    base = a
    while isinstance(base, np.ndarray) and base.base is not None:
        base = base.base
    # The buffer belongs to the C++ result, not to a NumPy copy.
    assert type(base).__name__ == "RunHandle"
    with pytest.raises(ValueError):
        a[0, 0] = 1.0


def test_loaded_result_saves_back_the_same_content(race, tmp_path):
    first = tmp_path / "a.h5"
    race.save(first)
    loaded = packsim.load(first)
    second = tmp_path / "b.h5"
    loaded.save(second)  # written by h5py this time
    again = packsim.load(second)
    assert again.keys() == loaded.keys()
    for k in loaded.keys():
        assert _same(loaded[k], again[k]), k
    assert again.attrs == loaded.attrs


def test_load_missing_file():
    with pytest.raises(FileNotFoundError):
        packsim.load("/nonexistent/result.h5")


def test_dataframe_and_xarray(race):
    pd = pytest.importorskip("pandas")
    df = race.to_dataframe()
    assert df.index.name == "time_s" and len(df) == race.n_samples
    np.testing.assert_array_equal(df["truth/pack_current_A"].to_numpy(), race["truth/pack_current_A"])
    np.testing.assert_array_equal(df["truth/cell_voltage_V[12]"].to_numpy(), race["truth/cell_voltage_V"][:, 11])
    tidy = race.to_dataframe("cells")
    assert len(tidy) == race.n_samples * race.n_cells
    row = tidy[(tidy.cell == 3)].iloc[10]
    assert row.cell_soc == race["truth/cell_soc"][10, 2]
    ev = race.to_dataframe("events")
    assert list(ev.columns) == ["time_s", "kind", "detail"] and len(ev) == len(race.events)
    assert isinstance(df, pd.DataFrame)
    with pytest.raises(ValueError):
        race.to_dataframe("nope")



def test_missing_optional_dependency_is_a_clear_error(race, monkeypatch):
    import sys
    monkeypatch.setitem(sys.modules, "pandas", None)
    with pytest.raises(ImportError, match="pip install pandas"):
        race.to_dataframe()


def test_recorded_arrays_are_at_hand_before_the_file_is_read(simple_yaml):
    """packsim.run hands back the recorded arrays at once; the in-memory file (attributes,
    summary, events) is built on first need, and then lists those very arrays."""
    r = packsim.run(simple_yaml, seed=3)
    early = {k: r[k] for k in ("time_s", "truth/cell_voltage_V", "measured/cell_voltage_mV", "bms/state")}
    assert r.n_cells == 3 and r.n_samples == early["time_s"].shape[0]
    assert r._ds is None  # nothing built or parsed yet
    assert r.summary["duration_s"] > 0 and r.events  # builds and reads the file
    assert r._ds is not None
    for k, a in early.items():
        assert r[k] is a and r.datasets[k] is a, k
    fresh = packsim.run(simple_yaml, seed=3)
    fresh.attrs  # read the file first this time
    for k, a in early.items():
        assert _same(fresh[k], a), k


def test_to_xarray_is_the_file_as_xarray_reads_it(race, tmp_path):
    """to_xarray() has the groups, names, dimensions, coordinates and attributes that
    xarray itself reads from the saved file, and the values of the Result; enumerated
    channels are categoricals of their names."""
    xr = pytest.importorskip("xarray")
    pytest.importorskip("h5netcdf")
    path = tmp_path / "race.h5"
    race.save(path)
    dt = race.to_xarray()
    with xr.open_datatree(path, engine="h5netcdf") as f:
        for group in ("truth", "measured", "bms", "hardware"):
            mine, theirs = dt[group].to_dataset(), f[group].to_dataset()
            assert sorted(mine.data_vars) == sorted(theirs.data_vars), group
            assert dict(mine.sizes) == dict(theirs.sizes), group
            for name, v in theirs.data_vars.items():
                assert mine[name].dims == v.dims, f"{group}/{name}"
                for k in ("units", "long_name"):
                    assert mine[name].attrs.get(k) == v.attrs.get(k), f"{group}/{name}.{k}"
                if "names" not in v.attrs:
                    np.testing.assert_array_equal(mine[name].values, race[f"{group}/{name}"])
            for d in mine.dims:
                if d != "time_s":
                    np.testing.assert_array_equal(mine[d].values, theirs[d].values)
            assert dt[group].attrs == f[group].attrs
        assert dt["summary"].attrs == f["summary"].attrs
    assert dt["truth/cell_voltage_V"].dims == ("time_s", "cell")
    assert float(dt["truth/cell_soc"].sel(cell=3).isel(time_s=10)) == race["truth/cell_soc"][10, 2]
    np.testing.assert_array_equal(dt["time_s"].values, race.time_s)
    state = dt["bms/state"]
    assert str(state.dtype) == "category"
    names = dict(item.split("=") for item in race.attrs["bms/state"]["names"].split(","))
    np.testing.assert_array_equal(np.asarray(state.values, dtype=object),
                                  [names[str(c)] for c in race["bms/state"]])
    assert list(dt["events"].values["kind"]) == [e["kind"] for e in race.events]


def test_a_mistyped_name_is_an_error_not_none(race):
    """r.units("truth/cell_voltage") (a typo) returned None, which reads as "no unit";
    r.faults("latchd") raised KeyError "no dataset 'bms/fault_latchd'", a name never typed."""
    with pytest.raises(KeyError, match="no dataset 'truth/cell_voltage' in this result"):
        race.units("truth/cell_voltage")
    assert race.units("bms/state") is None  # a dataset without a unit is still None
    with pytest.raises(ValueError, match=r"^which must be 'active' or 'latched', not 'latchd'$"):
        race.faults("latchd")
