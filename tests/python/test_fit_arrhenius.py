"""packsim.fit over several temperatures as one joint fit (temperature_law "arrhenius",
the default): a known cell whose R0, RC resistances and time constants follow Arrhenius
laws is driven by packsim's own plant — an HPPC at 25 °C (the only rests) and 1C
constant-current discharges at 0, 25 and 40 °C without any rest, each heating itself —
and the fit recovers the laws from every sample at its measured temperature."""
from __future__ import annotations

import numpy as np
import pytest
import yaml

import packsim
from fit_cells import KNOWN_CELL, KNOWN_R0_OHM, KNOWN_RC, SOC_GRID, hppc_segments, simulate, write_test_csv

R0_K = 3500.0
RC_R_K = 3000.0
TAU_K = 1200.0
CC_TEMPS_C = (0.0, 25.0, 40.0)


def _cell() -> dict:
    law = {"arrhenius_K": RC_R_K, "ref_temp_C": 25.0}
    return dict(KNOWN_CELL, r0_ohm=dict(KNOWN_CELL["r0_ohm"], arrhenius_K=R0_K, ref_temp_C=25.0),
                rc_pairs=[{"r_ohm": dict(law, poly=[p["r_ohm"]]),
                           "tau_s": {"poly": [p["tau_s"]], "arrhenius_K": TAU_K, "ref_temp_C": 25.0}}
                          for p in KNOWN_RC],
                heat_capacity_J_per_K=70.0, g_ambient_W_per_K=0.25)  # it warms under load


@pytest.fixture(scope="module")
def tests(tmp_path_factory):
    folder = tmp_path_factory.mktemp("arrhenius")
    cell = _cell()
    files = [write_test_csv(simulate(cell, hppc_segments(5.0, rest_s=900.0)), folder / "hppc_25C.csv", seed=5)]
    for k, t in enumerate(CC_TEMPS_C):  # 1C from full to SOC 0.15, no rest before or after
        files.append(write_test_csv(simulate(cell, [(3060.0, 5.0)], ambient_C=t), folder / f"cc_{t:g}C.csv",
                                    seed=11 + k))
    return [str(p) for p in files]


@pytest.fixture(scope="module")
def fitted(tests):
    return packsim.fit(tests, rc_pairs=2, capacity_Ah=5.0)


def test_the_cells_heat_themselves(tests):
    cold = np.loadtxt(tests[1], delimiter=",", skiprows=1)
    assert cold[-1, 3] - cold[0, 3] > 8.0  # so a file's first temperature would be wrong


def test_arrhenius_laws_recovered(fitted):
    assert fitted.temperature_law == "arrhenius"
    (g,) = fitted.temperatures
    assert g.r0_K == pytest.approx(R0_K, rel=0.03)
    assert fitted.params["temperatures"][0]["arrhenius_K"]["r0"] == g.r0_K
    for k, pair in enumerate(KNOWN_RC):
        assert g.rc_r_ohm[k, 0] == pytest.approx(pair["r_ohm"], rel=0.05), k
        assert g.rc_tau_s[k] == pytest.approx(pair["tau_s"], rel=0.10), k
    assert g.rc_r_K == pytest.approx([RC_R_K, RC_R_K], rel=0.10)
    assert g.rc_tau_K == pytest.approx([TAU_K, TAU_K], abs=400.0)


def test_r0_at_every_temperature(fitted):
    for temp_C in (0.0, 25.0, 40.0):
        factor = np.exp(R0_K * (1 / (temp_C + 273.15) - 1 / 298.15))
        for soc in (0.9, 0.6, 0.3):
            truth = factor * np.interp(soc, SOC_GRID, KNOWN_R0_OHM)
            assert fitted.r0_ohm(soc, temp_C=temp_C) == pytest.approx(truth, rel=0.03), (temp_C, soc)


def test_every_file_reproduced(fitted):
    assert [f.name.rsplit("/", 1)[-1] for f in fitted.files] == ["hppc_25C.csv", "cc_0C.csv", "cc_25C.csv",
                                                                 "cc_40C.csv"]
    for f in fitted.files:
        assert 1.5 < f.rms_mV < 3.0, (f.name, f.rms_mV)  # the 2 mV sensor noise


def test_preset_carries_the_laws_and_loads(fitted, tmp_path):
    cell = yaml.safe_load(fitted.yaml)
    assert cell["r0_ohm"]["arrhenius_K"] == pytest.approx(fitted.temperatures[0].r0_K)
    assert cell["rc_pairs"][1]["tau_s"]["ref_temp_C"] == 25
    (tmp_path / "cells").mkdir()
    fitted.save(tmp_path / "cells" / "fitted.yaml")
    thermal = {"heat_capacity_J_per_K": 70.0, "g_ambient_W_per_K": 0.25}  # not fitted: the cell's
    cold = simulate({"preset": "fitted", **thermal}, [(600.0, 5.0)], ambient_C=0.0, base_dir=tmp_path)
    truth = simulate(_cell(), [(600.0, 5.0)], ambient_C=0.0)
    err = cold["truth/cell_voltage_V"][:, 0] - truth["truth/cell_voltage_V"][:, 0]
    assert np.max(np.abs(err)) < 0.01


def test_a_file_label_is_not_its_temperature_any_more(tests):
    # the table law needs a rest at every temperature: the cold discharge has none
    with pytest.raises(packsim.FitError, match=r"cc_0C.csv: no rest at 0.0 °C .*temperature_law arrhenius"):
        packsim.fit(tests, rc_pairs=2, capacity_Ah=5.0, temperature_law="table")
