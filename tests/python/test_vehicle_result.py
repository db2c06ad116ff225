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
