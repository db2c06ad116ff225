"""A vehicle run over distance: packsim.plot.vehicle (PNG) and the report's "Over
distance" figure (packsim.vehicle_figure) draw speed, pack power, SOC and the lowest
cell against the km driven, from the result file's /vehicle group."""
from __future__ import annotations

import json
import re

import numpy as np
import pytest

import packsim
from packsim import plot
from packsim.vehicle_figure import distance_series, has_vehicle


@pytest.fixture(scope="module")
def limited_car():
    # The eco car with its controller at 12 A: the pack limits it while it accelerates
    # on the first flat (tests/core/vehicle_race_test.cpp); two laps of 1.6 km.
    return packsim.run("vehicle/eco_marathon_12s_circuit",
                       {"load.vehicle.max_current_A": 12, "run.solver": "fast", "load.route.laps": 2, "expect": {}})


def test_series_are_the_result_over_its_distance(limited_car, race):
    r = limited_car
    assert has_vehicle(r) and not has_vehicle(race)
    d = distance_series(r)
    assert d.km[-1] == pytest.approx(3.2, abs=1e-3)  # two laps, finished (within the last tick)
    assert np.all(np.diff(d.km) >= 0.0)
    assert d.speed_kmh.max() == pytest.approx(27.0, abs=0.05)
    np.testing.assert_array_equal(d.pack_W, r["truth/pack_voltage_V"] * r["truth/pack_current_A"])
    np.testing.assert_array_equal(d.min_cell_V, r["truth/cell_voltage_V"].min(axis=1))
    # The first pack limit: where the car was at vehicle_limit_time_s, inside the first flat.
    t_lim = r.summary["vehicle_limit_time_s"]
    assert t_lim >= 0.0
    assert 0.0 <= d.limit_km < 0.6
    assert d.limit_km == pytest.approx(np.interp(t_lim, r.time_s, r["vehicle/distance_m"]) / 1000.0)
    assert d.undervoltage_V == pytest.approx(float(r.attrs["bms"]["limit_cell_undervoltage_V"]))
    with pytest.raises(ValueError, match="not a vehicle run"):
        distance_series(race)


def test_png_figure_and_plot_all(limited_car, race, tmp_path):
    fig = plot.vehicle(limited_car)
    assert len(fig.axes) == 4 and fig.axes[3].get_xlabel() == "distance (km)"
    xs = fig.axes[0].lines[0].get_xdata()
    np.testing.assert_array_equal(xs, limited_car["vehicle/distance_m"] / 1000.0)
    assert plot.vehicle(race) is None
    paths = plot.plot_all(limited_car, tmp_path)
    assert any(p.endswith("_vehicle_distance.png") for p in paths), paths


def test_report_has_the_figure_over_distance(limited_car):
    pytest.importorskip("plotly")
    from packsim.report import result_html
    text = result_html(limited_car)
    assert "<h2>Over distance</h2>" in text
    m = re.search(r'Plotly\.newPlot\(\s*"distance-figure",\s*(\[.*?\]),\s*(\{.*?\}),\s*\{', text, re.S)
    assert m, "no distance figure"
    names = {t["name"] for t in json.loads(m.group(1))}
    assert {"speed", "pack power (delivered)", "mean cell SOC", "lowest cell voltage"} <= names
    assert "first pack limit, km 0." in text
