"""The fitter's simulation (C++, core/fit/ecm_zoh.hpp: an exact zero-order hold of the
plant's cell equations) against packsim's plant (CVODE over the same current profile):
the same terminal voltage. And its analytic derivatives against finite differences."""
from __future__ import annotations

import numpy as np
import pytest
import yaml

import packsim
from fit_cells import KNOWN_CELL, KNOWN_RC, hppc_segments, simulate
from packsim import _packsim

CAPACITY_AH = KNOWN_CELL["capacity_Ah"]


def _profile(segments, step_s: float, end_s: float):
    """Sample times every step_s and the segment current at each (segments change at
    half seconds, so a step_s of 0.5 puts a sample on every change)."""
    t = np.arange(0.0, end_s + step_s / 2, step_s)
    edges = np.cumsum([d for d, _ in segments])
    currents = np.array([i for _, i in segments])
    # the current flowing just after each sample: held over the interval that follows
    held = currents[np.minimum(np.searchsorted(edges, t, side="right"), len(currents) - 1)]
    return t, held


@pytest.mark.parametrize("arrhenius", [False, True])
def test_zoh_simulation_equals_the_plant(arrhenius):
    cell = dict(KNOWN_CELL, g_ambient_W_per_K=5.0)
    if arrhenius:  # a temperature law, the cell held near its 10 °C ambient
        cell["r0_ohm"] = dict(cell["r0_ohm"], arrhenius_K=3000.0, ref_temp_C=25.0)
        cell["rc_pairs"] = [{"r_ohm": {"poly": [p["r_ohm"]], "arrhenius_K": 2500.0, "ref_temp_C": 25.0},
                             "tau_s": {"poly": [p["tau_s"]], "arrhenius_K": 800.0, "ref_temp_C": 25.0}}
                            for p in cell["rc_pairs"]]
    segments = hppc_segments(CAPACITY_AH, steps=3, rest_s=600.0)
    ambient = 10.0 if arrhenius else 25.0
    plant = simulate(cell, segments, ambient_C=ambient)
    t_plant = plant.time_s
    v_plant = plant["truth/cell_voltage_V"][:, 0]
    temp_plant = plant["truth/cell_temp_C"][:, 0]
    t, held = _profile(segments, 0.5, t_plant[-1])
    temp = np.interp(t, t_plant, temp_plant)
    # at the samples compared (whole seconds) no step happens: the current there is the held one
    v = _packsim.simulate_cell(yaml.safe_dump(cell), t, held, held, temp, 1.0)
    on_plant = np.searchsorted(t, t_plant)
    assert np.array_equal(t[on_plant], t_plant)
    err = v[on_plant] - v_plant
    assert np.max(np.abs(v_plant - v_plant[0])) > 0.3          # the profile moves the voltage
    # CVODE's tolerance (and, with the temperature law, T frozen over each 0.5 s) is all
    # that separates the two
    assert np.max(np.abs(err)) < 2e-5, np.max(np.abs(err))


def test_rc_response_is_the_exact_step_response():
    t = np.array([0.0, 0.5, 2.0, 7.0, 7.1])
    v = _packsim.rc_response(t, np.full(5, 2.0), np.array([3.0]))
    assert v == pytest.approx(2.0 * (1.0 - np.exp(-t / 3.0)), rel=1e-14, abs=1e-15)


def test_rc_sensitivity_matches_finite_differences():
    rng = np.random.default_rng(3)
    t = np.cumsum(rng.uniform(0.2, 2.0, 400))
    x = rng.normal(0.0, 1.0, 400)
    g = rng.uniform(-1e-4, 1e-4, 400)          # d log tau / d theta_2, as 1/T_K - 1/T_ref does
    theta = np.array([np.log(20.0), 500.0])

    def tau(th):
        return np.exp(th[0] + th[1] * g)

    v, s = _packsim.rc_sensitivity(t, x, tau(theta), np.column_stack([np.ones_like(g), g]))
    assert v == pytest.approx(_packsim.rc_response(t, x, tau(theta)), rel=0, abs=1e-15)
    for j, h in enumerate((1e-6, 1e-3)):
        up, down = theta.copy(), theta.copy()
        up[j] += h
        down[j] -= h
        fd = (_packsim.rc_response(t, x, tau(up)) - _packsim.rc_response(t, x, tau(down))) / (2 * h)
        assert s[:, j] == pytest.approx(fd, rel=1e-5, abs=1e-9)


def test_bad_arguments_are_value_errors():
    t = np.arange(5.0)
    with pytest.raises(ValueError, match="tau_s"):
        _packsim.rc_response(t, np.ones(5), np.array([0.0]))
    with pytest.raises(ValueError, match="x: 4 values, expected 5"):
        _packsim.rc_response(t, np.ones(4), np.array([1.0]))
    with pytest.raises(ValueError, match="capacity_Ah"):
        _packsim.simulate_cell("ocv_V: 3.7\n", t, t, t, t, 1.0)


def test_steps_on_the_samples_bias_r0_unless_said(tmp_path):
    """An HPPC whose current steps land on the 1 s samples, each step sample reading the new
    current (as packsim records it). The default held current, the mean of each interval's
    ends, gives the interval before a step half the step it did not carry: R0 comes out low
    by about sum_j R_j (1 - exp(-dt/tau_j)) / 2 (docs/fit.md), 1.7 % here. Holding each
    sample's current over the interval after it (steps_on_samples) is exact for such a
    record: R0 within 0.3 %. Noise-free data, R0 constant over SOC."""
    from fit_cells import write_test_csv
    cell = dict(KNOWN_CELL, r0_ohm=0.02)
    c = CAPACITY_AH
    segments = [(60.0, 0.0)]  # whole seconds: every step on a sample
    for _ in range(9):
        segments += [(10.0, c), (40.0, 0.0), (10.0, -0.75 * c), (40.0, 0.0), (720.0, 0.5 * c), (1800.0, 0.0)]
    path = write_test_csv(simulate(cell, segments), tmp_path / "hppc_on_samples.csv", noise_V=0.0, noise_A=0.0)
    socs = (0.3, 0.5, 0.7, 0.9)
    bias = sum(p["r_ohm"] * -np.expm1(-1.0 / p["tau_s"]) for p in KNOWN_RC) / 2.0 / 0.02
    assert bias == pytest.approx(0.017, abs=0.0005)

    default = packsim.fit(str(path), rc_pairs=2, capacity_Ah=c)
    for soc in socs:
        low = 1.0 - default.r0_ohm(soc) / 0.02
        assert 0.8 * bias < low < 1.3 * bias, (soc, low)

    exact = packsim.fit(str(path), rc_pairs=2, capacity_Ah=c, steps_on_samples=True)
    for soc in socs:
        assert exact.r0_ohm(soc) == pytest.approx(0.02, rel=0.003), soc
    assert exact.files[0].rms_mV < default.files[0].rms_mV
