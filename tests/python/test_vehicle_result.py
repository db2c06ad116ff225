"""A vehicle run's result (docs/vehicle.md): the /vehicle group opens in xarray with the
distance driven as a coordinate of its series, so a channel can be read by place."""
from __future__ import annotations

import numpy as np
import pytest

import packsim

xr = pytest.importorskip("xarray")
pytest.importorskip("h5netcdf")


def test_distance_is_a_coordinate_of_the_vehicle_series(tmp_path):
    r = packsim.run("vehicle/eco_marathon_12s_circuit", {"run.duration_s": 120})
    f = tmp_path / "eco.h5"
    r.save(f)
    ds = xr.open_dataset(f, group="vehicle", engine="h5netcdf")
    assert "distance_m" in ds.coords
    d = ds["distance_m"].values
    assert np.all(np.diff(d) >= 0.0) and d[-1] > 600.0
    # By place: on the 3 % climb (600..850 m) the car holds its 27 km/h.
    by_place = ds["speed_m_per_s"].swap_dims({"time_s": "distance_m"})
    assert by_place.sel(distance_m=700.0, method="nearest").item() == pytest.approx(27 / 3.6, rel=1e-3)
    np.testing.assert_array_equal(ds["distance_m"].values, r["vehicle/distance_m"])


def test_the_lap_table_is_in_the_result_file_and_the_report(tmp_path):
    # The circuit is 1.6 km a lap; 500 s at about 27 km/h: two laps crossed, the third
    # the run ended in.
    r = packsim.run("vehicle/eco_marathon_12s_circuit", {"run.duration_s": 500})
    laps = r["vehicle/laps"]
    assert list(laps["lap"]) == [1, 2, 3]
    assert list(laps["complete"]) == [1, 1, 0]
    np.testing.assert_allclose(laps["distance_m"][:2], 1600.0, rtol=1e-9)
    # The laps add up to the run: distance driven and the pack's energy (summary attributes).
    assert laps["distance_m"].sum() == pytest.approx(r.summary["vehicle_distance_km"] * 1000.0, rel=1e-9)
    assert laps["pack_Wh"].sum() == pytest.approx(r.summary["vehicle_pack_Wh"], rel=1e-9)
    # Each lap starts where the one before ended.
    np.testing.assert_allclose(laps["start_s"][1:], laps["start_s"][:-1] + laps["time_s"][:-1], rtol=1e-12)
    f = tmp_path / "eco.h5"
    r.save(f)
    from packsim.report import result_html
    page = result_html(f)
    assert "<h3>Laps (3)</h3>" in page and 'id="laps"' in page
    assert "no (the run ended in it)" in page
    xr.open_dataset(f, group="vehicle", engine="h5netcdf")  # the compound table does not stop xarray
