"""packsim.fit with tests at several temperatures and temperature_law "table": one fit per
temperature, written as 2-D tables over SOC × temp_C (the joint Arrhenius fit is in
test_fit_arrhenius.py). Here only the fit; loading such a preset is in
test_fit_tables_load.py."""
from __future__ import annotations

import numpy as np
import pytest
import yaml

import packsim
from fit_cells import KNOWN_R0_OHM, KNOWN_RC, RESISTANCE_SCALE_AT_C, SOC_GRID, hppc_segments, known_cell_at, \
    simulate, write_test_csv

TEMPS_C = sorted(RESISTANCE_SCALE_AT_C)


@pytest.fixture(scope="module")
def tests_at_temperatures(tmp_path_factory):
    folder = tmp_path_factory.mktemp("temps")
    return [write_test_csv(simulate(known_cell_at(t), hppc_segments(5.0, rest_s=900.0), ambient_C=t),
                           folder / f"hppc_{t:g}C.csv", seed=int(t) + 3) for t in TEMPS_C]


@pytest.fixture(scope="module")
def fitted(tests_at_temperatures):
    return packsim.fit([str(p) for p in reversed(tests_at_temperatures)], rc_pairs=2, capacity_Ah=5.0,
                       temperature_law="table")


def test_one_fit_per_temperature(fitted):
    assert [round(g.temp_C) for g in fitted.temperatures] == TEMPS_C
    assert all(f.rms_mV < 5.0 for f in fitted.files)
    for k, t in enumerate(TEMPS_C):
        scale = RESISTANCE_SCALE_AT_C[t]
        for soc in (0.9, 0.6, 0.3):
            truth = scale * np.interp(soc, SOC_GRID, KNOWN_R0_OHM)
            assert fitted.r0_ohm(soc, temperature=k) == pytest.approx(truth, rel=0.02), (t, soc)
        g = fitted.temperatures[k]
        for p, pair in enumerate(KNOWN_RC):
            assert g.rc_r_ohm[p, 0] == pytest.approx(scale * pair["r_ohm"], rel=0.05), (t, p)


def test_preset_has_2d_tables(fitted):
    cell = yaml.safe_load(fitted.yaml)
    for curve in (cell["ocv_V"], cell["r0_ohm"], cell["rc_pairs"][0]["r_ohm"], cell["rc_pairs"][1]["tau_s"]):
        assert curve["axis"] == "soc"
        assert [round(t) for t in curve["temp_C"]] == TEMPS_C
        assert len(curve["y"]) == 3 and all(len(row) == len(curve["x"]) for row in curve["y"])
    r0 = np.array(cell["r0_ohm"]["y"])
    assert np.all(r0[0] > 2 * r0[1])  # 0 °C rows well above 25 °C


def test_poly_form_refuses_several_temperatures(tests_at_temperatures):
    with pytest.raises(packsim.FitError, match="form poly fits one temperature"):
        packsim.fit([str(p) for p in tests_at_temperatures], form="poly", rc_pairs=0, capacity_Ah=5.0,
                    temperature_law="table")
