"""State estimation channels: the summary's SOC error figures are exactly what the
recorded estimates and truth say when every tick is recorded, and the result layout
holds both estimates, the per-group EKF, the capacity estimate and the display bars."""
from __future__ import annotations

import numpy as np
import pytest

import packsim


@pytest.fixture(scope="module")
def every_tick():
    # One lap of the default race with a drifting current offset, every 10 ms tick recorded.
    return packsim.run(overrides={
        "load.laps": 1, "output.interval_s": 0.01, "bms.soc.estimator": "ekf",
        "faults": [{"kind": "current_sensor_drift", "offset_A": 0.5, "at_s": 0}],
    })


def test_summary_errors_are_the_recorded_ones(every_tick):
    r, s = every_tick, every_tick.summary
    truth = r["truth/soc_mean"]
    assert s["soc_estimator"] == "ekf"
    for name in ("coulomb", "ekf"):
        err = r[f"bms/soc_{name}"] - truth
        assert s[f"soc_error_{name}_max"] == pytest.approx(np.abs(err).max(), abs=1e-12)
        assert s[f"soc_error_{name}_rms"] == pytest.approx(np.sqrt(np.mean(err**2)), abs=1e-12)
        assert s[f"soc_error_{name}_end"] == pytest.approx(err[-1], abs=1e-12)
    # The reported estimate is the EKF's, in 0.1 %.
    np.testing.assert_allclose(r["bms/soc_estimate_permille"] / 1000.0, r["bms/soc_ekf"], atol=0.0005 + 1e-7)
    # A +0.5 A offset for 262 s over 5 Ah: coulomb counting ends 0.73 % low (healthy: ~0.1 %).
    assert s["soc_error_coulomb_end"] == pytest.approx(-0.5 * 262 / 18000, abs=0.002)


def test_estimation_layout(every_tick):
    r = every_tick
    n, series = r.n_samples, 12
    assert r["bms/soc_ekf_group_permille"].shape == (n, series)
    assert r["bms/soc_ekf_group_permille"].dtype == np.uint16
    for k in ("bms/soc_coulomb", "bms/soc_ekf", "truth/soc_mean", "bms/capacity_estimate_Ah"):
        assert r[k].shape == (n,) and r[k].dtype == np.float64, k
    for k in ("bms/soc_display_bars", "truth/soc_display_bars"):
        bars = r[k]
        assert bars.dtype == np.uint8 and bars.min() >= 1 and bars.max() <= 8, k
    # The group EKFs average to the pack EKF (to the 0.1 % of the group channel).
    np.testing.assert_allclose(r["bms/soc_ekf_group_permille"].mean(axis=1) / 1000.0, r["bms/soc_ekf"], atol=6e-4)
    assert {"capacity_estimate_Ah", "capacity_true_Ah", "display_bars_hidden_max",
            "soc_error_ekf_group_max", "soc_error_ekf_group"} <= set(r.summary)
