"""Fitted presets that need the cell-curve loader of issue 11's model work (2-D tables
over SOC × temp_C, RC resistances and time constants as tables): loaded by name into a
scenario, they reproduce the tests through the simulator, and the same preset gives a
colder run a lower voltage under load."""
from __future__ import annotations

import numpy as np

import packsim
from fit_cells import hppc_segments, simulate
from test_fit_temperature import TEMPS_C, fitted, tests_at_temperatures  # noqa: F401 (fixtures)

CHAMBER = {"g_ambient_W_per_K": 2.0}  # the cell held near its chamber temperature, as in the tests


def _rms_V(result, csv_path) -> float:
    measured = np.loadtxt(csv_path, delimiter=",", skiprows=1)
    n = min(result.time_s.size, measured.shape[0])
    return float(np.sqrt(np.mean((result["truth/cell_voltage_V"][:n, 0] - measured[:n, 2]) ** 2)))


def test_2d_preset_reproduces_each_temperature(fitted, tests_at_temperatures, tmp_path):  # noqa: F811
    (tmp_path / "cells").mkdir()
    fitted.save(tmp_path / "cells" / "fitted_2d.yaml")
    for t, csv_path in zip(TEMPS_C, tests_at_temperatures):
        r = simulate({"preset": "fitted_2d", **CHAMBER}, hppc_segments(5.0, rest_s=900.0), ambient_C=t,
                     base_dir=tmp_path)
        assert _rms_V(r, csv_path) < 0.006, t


def test_2d_preset_cold_and_hot_runs_differ(fitted, tmp_path):  # noqa: F811
    (tmp_path / "cells").mkdir()
    fitted.save(tmp_path / "cells" / "fitted_2d.yaml")
    lowest = {t: simulate({"preset": "fitted_2d", **CHAMBER}, [(60.5, 0.0), (600.0, 5.0)], ambient_C=t,
                          base_dir=tmp_path).summary["min_cell_V"] for t in (-15.0, 45.0)}
    assert lowest[-15.0] < lowest[45.0] - 0.05


def test_rc_over_soc_preset_loads_and_reproduces(tests_at_temperatures, tmp_path):  # noqa: F811
    at_25 = str(tests_at_temperatures[TEMPS_C.index(25.0)])
    f = packsim.fit(at_25, rc_pairs=2, capacity_Ah=5.0, rc_over_soc=True)
    assert f.files[0].rms_mV < 5.0
    (tmp_path / "cells").mkdir()
    f.save(tmp_path / "cells" / "fitted_rc_soc.yaml")
    r = simulate({"preset": "fitted_rc_soc", **CHAMBER}, hppc_segments(5.0, rest_s=900.0), base_dir=tmp_path)
    assert _rms_V(r, at_25) < 0.006
