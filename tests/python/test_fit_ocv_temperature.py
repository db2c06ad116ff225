"""packsim.fit's OCV temperature coefficient: a known cell whose OCV moves with temperature
(OCV(soc, T) = OCV(soc) + (T - 25 °C)·dOCV/dT(soc), a 2-D table in the preset, with the
same coefficient for its reversible heat) is driven by packsim's own plant through HPPC
tests at 10 and 40 °C; the joint fit recovers dOCV/dT over SOC from the rests, writes it
to the preset (2-D OCV + docv_dT_V_per_K) and reproduces both files to the sensor noise,
where one OCV for both temperatures cannot."""
from __future__ import annotations

import numpy as np
import pytest
import yaml

import packsim
from fit_cells import KNOWN_CELL, KNOWN_OCV_V, SOC_GRID, hppc_segments, simulate, write_test_csv

DOCV_DT = np.interp(SOC_GRID, [0.0, 0.5, 1.0], [-0.4e-3, 0.1e-3, 0.3e-3])  # V/K
TEMPS_C = (10.0, 40.0)
ROWS_C = [0.0, 50.0]


def _ocv_rows() -> list[list[float]]:
    return [list(np.asarray(KNOWN_OCV_V) + (t - 25.0) * DOCV_DT) for t in ROWS_C]


def _cell() -> dict:
    return dict(KNOWN_CELL, ocv_V={"x": SOC_GRID, "temp_C": ROWS_C, "y": _ocv_rows()},
                docv_dT_V_per_K={"x": SOC_GRID, "y": list(DOCV_DT)}, g_ambient_W_per_K=2.0)


@pytest.fixture(scope="module")
def tests(tmp_path_factory):
    folder = tmp_path_factory.mktemp("ocv_dT")
    return [str(write_test_csv(simulate(_cell(), hppc_segments(5.0, rest_s=900.0), ambient_C=t),
                               folder / f"hppc_{t:g}C.csv", seed=21 + k)) for k, t in enumerate(TEMPS_C)]


@pytest.fixture(scope="module")
def fitted(tests):
    return packsim.fit(tests, rc_pairs=2, capacity_Ah=5.0)


def test_the_coefficient_is_recovered_over_soc(fitted):
    assert fitted.temperature_law == "arrhenius"
    lo, hi = fitted.ocv_temps_C
    assert 9.0 < lo < 11.0 and 39.0 < hi < 42.0
    soc = np.arange(0.15, 0.95, 0.05)  # between the HPPC's rests (SOC 0.1 .. 1)
    truth = np.interp(soc, SOC_GRID, DOCV_DT)
    assert np.max(np.abs(fitted.docv_dT_V_per_K(soc) - truth)) < 0.06e-3  # V/K: 1.8 mV over the 30 K
    # the OCV's change between the two tests' temperatures: the coefficient times 30 K
    shift = fitted.ocv_V(soc, temp_C=40.0) - fitted.ocv_V(soc, temp_C=10.0)
    assert np.max(np.abs(shift - 30.0 * truth)) < 1.8e-3
    assert np.all(fitted.ocv_V(soc, temp_C=25.0) == fitted.ocv_V(soc))  # the 25 °C row is the fitted OCV


def test_the_preset_carries_it_and_reproduces_both_files(fitted):
    cell = yaml.safe_load(fitted.yaml)
    assert cell["ocv_V"]["temp_C"] == pytest.approx(list(fitted.ocv_temps_C))
    assert len(cell["ocv_V"]["y"]) == 2
    assert cell["docv_dT_V_per_K"]["y"] == pytest.approx(list(fitted.temperatures[0].docv_dT_V_per_K), rel=1e-6)
    for f in fitted.files:  # re-simulated through the preset loader and the plant's curves
        assert f.rms_mV < 3.0, (f.name, f.rms_mV)  # the 2 mV sensor noise


def test_one_ocv_for_both_temperatures_cannot(tests, fitted):
    without = packsim.fit(tests, rc_pairs=2, capacity_Ah=5.0, ocv_temperature=False)
    assert without.ocv_temps_C is None and without.temperatures[0].docv_dT_V_per_K is None
    assert "docv_dT_V_per_K" not in yaml.safe_load(without.yaml)
    worst = max(f.rms_mV for f in without.files)
    assert worst > 1.5 * max(f.rms_mV for f in fitted.files), worst


def test_rests_at_one_temperature_do_not_determine_it(tests):
    with pytest.raises(packsim.FitError, match="rests at temperatures more than 3 °C apart"):
        packsim.fit(tests[:1], rc_pairs=2, capacity_Ah=5.0, ocv_temperature=True)
    f = packsim.fit(tests[:1], rc_pairs=2, capacity_Ah=5.0)  # automatic: left out, no warning needed
    assert f.ocv_temps_C is None
