"""packsim.fit on synthetic HPPC data from packsim's own plant: the known cell comes back
(R0 within 2 %, RC resistances within 5 %, voltage within 5 mV RMS), and the fitted
preset, loaded by name into a scenario, reproduces the measured voltage through the
simulator."""
from __future__ import annotations

import numpy as np
import pytest
import yaml

import packsim
from fit_cells import KNOWN_CELL, KNOWN_OCV_V, KNOWN_R0_OHM, KNOWN_RC, SOC_GRID, hppc_segments, simulate, \
    write_test_csv

CAPACITY_AH = KNOWN_CELL["capacity_Ah"]


@pytest.fixture(scope="module")
def hppc(tmp_path_factory):
    folder = tmp_path_factory.mktemp("hppc")
    result = simulate(KNOWN_CELL, hppc_segments(CAPACITY_AH))
    return write_test_csv(result, folder / "hppc_25C.csv")


@pytest.fixture(scope="module")
def fitted(hppc):
    return packsim.fit(str(hppc), rc_pairs=2, capacity_Ah=CAPACITY_AH)


def test_voltage_within_5mV_rms(fitted):
    (f,) = fitted.files
    assert f.samples > 20000
    assert f.rms_mV < 5.0
    # the noise added is 2 mV RMS: the model cannot do (much) better than that
    assert f.rms_mV > 1.5


def test_r0_within_2_percent_where_pulsed(fitted):
    # The HPPC pulses sit at SOC 1.0, 0.9, ..., 0.2: there R0 is measured directly.
    for soc in np.round(np.arange(1.0, 0.15, -0.1), 2):
        truth = np.interp(soc, SOC_GRID, KNOWN_R0_OHM)
        assert fitted.r0_ohm(soc) == pytest.approx(truth, rel=0.02), soc


def test_rc_pairs_within_5_percent(fitted):
    g = fitted.temperatures[0]
    assert g.rc_tau_s.tolist() == sorted(g.rc_tau_s.tolist())
    for k, pair in enumerate(KNOWN_RC):
        assert g.rc_r_ohm[k, 0] == pytest.approx(pair["r_ohm"], rel=0.05)
        assert g.rc_tau_s[k] == pytest.approx(pair["tau_s"], rel=0.10)


def test_ocv_rises_strictly_and_matches_at_rest_points(fitted):
    ocv = fitted.temperatures[0].ocv_V
    assert np.all(np.diff(ocv) > 0)
    # the rests end at SOC 1.0, 0.9 ... 0.1 (less the pulses' net 12.5 As): OCV there within 3 mV
    for soc in np.round(np.arange(1.0, 0.15, -0.1), 2):
        assert fitted.ocv_V(soc) == pytest.approx(np.interp(soc, SOC_GRID, KNOWN_OCV_V), abs=0.003), soc


def test_preset_text_is_a_valid_cell(fitted):
    cell = yaml.safe_load(fitted.yaml)
    assert cell["capacity_Ah"] == CAPACITY_AH
    assert cell["ocv_V"]["axis"] == "soc" and cell["ocv_V"]["x"][:3] == [0, 0.01, 0.02]
    assert cell["ocv_V"]["x"] == cell["r0_ohm"]["x"] and len(cell["ocv_V"]["x"]) == 25
    assert len(cell["rc_pairs"]) == 2 and set(cell["rc_pairs"][0]) == {"r_ohm", "tau_s"}
    assert "hppc_25C.csv" in fitted.yaml  # the report is in the preset's comment


def test_fitted_preset_reproduces_the_test_in_the_simulator(fitted, hppc, tmp_path):
    (tmp_path / "cells").mkdir()
    fitted.save(tmp_path / "cells" / "fitted_cell.yaml")
    measured = np.loadtxt(hppc, delimiter=",", skiprows=1)
    rerun = simulate({"preset": "fitted_cell"}, hppc_segments(CAPACITY_AH), base_dir=tmp_path)
    n = min(rerun.time_s.size, measured.shape[0])
    assert np.array_equal(rerun.time_s[:n], measured[:n, 0])
    err_V = rerun["truth/cell_voltage_V"][:n, 0] - measured[:n, 2]
    assert np.sqrt(np.mean(err_V ** 2)) < 0.005


def test_plot_writes_the_report(fitted, tmp_path):
    fig = fitted.plot(tmp_path / "fit.png")
    assert (tmp_path / "fit.png").stat().st_size > 10000
    assert len(fig.axes) == 2
