"""The generative campaign's smoke run (scripts/campaign.py; the long run and its figures:
docs/hardening.md): random valid scenarios -- packs of 1-250 series x 1-20 parallel,
bundled and fitted cells, segment/point/CSV loads with breakpoints at arbitrary
decimals, chargers, faults at random times, extends chains and overrides, both
integrators, the example firmware -- each judged by oracles that need no stored output.
Cases are capped at 20 simulated seconds here so the smoke stays well under a minute."""
import importlib.util
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


def _campaign():
    spec = importlib.util.spec_from_file_location("campaign", ROOT / "scripts" / "campaign.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


@pytest.mark.parametrize("first", [0, 8, 16])
def test_generated_scenarios_hold_every_oracle(tmp_path, first):
    campaign = _campaign()
    failed = []
    for i in range(first, first + 8):
        res = campaign.run_case(i, 20261125, tmp_path, keep=False, max_s=20.0)
        if res["findings"]:
            failed.append(res)
    assert not failed, "\n".join(f"case {f['case']} (scripts/campaign.py --seed 20261125 --only {f['case']}): "
                                 + " | ".join(f["findings"]) for f in failed)


def test_the_oracles_can_fail(tmp_path):
    """An oracle that cannot fail proves nothing: a result with a summary that the
    truth contradicts, and two runs that differ, are caught."""
    campaign = _campaign()
    import packsim
    yaml = ("pack: {series: 2, cell: {preset: lipo_5Ah}}\nload: {current_A: 2}\nrun: {duration_s: 5}\n"
            "bms: {tick_ms: 100}\noutput: {interval_s: 0.1}\n")
    r = packsim.run(yaml)
    assert campaign.check_physics({}, r) == []


    class Tampered:  # the same result with a summary the truth contradicts
        def __init__(self, r):
            self.events, self.summary = r.events, dict(r.summary, min_cell_V=r.summary["min_cell_V"] - 0.01)
            self._r = r

        def __getitem__(self, key):
            return self._r[key]

        def keys(self):
            return self._r.keys()

    assert any("lowest cell" in f for f in campaign.check_physics({}, Tampered(r)))
    # A hottest cell past 80 C without its cell_model_range event; a run that stopped at
    # 3 s of 5 claiming its scheduled end.
    hot = Tampered(r)
    hot.summary = dict(r.summary, max_temp_C=90.0)
    assert any("cell_model_range" in f for f in campaign.check_physics({}, hot))
    early = Tampered(r)
    early.summary = dict(r.summary, duration_s=3.0)
    assert any("says the scenario's end time" in f for f in campaign.check_physics({"run": {"duration_s": 5.0}}, early))
    # The SOC oracle: the same run holds it; a counter that says 1 % more was delivered
    # than the cells gave is caught.
    scen = {"pack": {"series": 2, "cell": {"preset": "lipo_5Ah"}}}
    assert campaign.check_soc(scen, r) == []
    more = Tampered(r)
    more.summary = dict(r.summary, charge_delivered_Ah=1.01 * r.summary["charge_delivered_Ah"])
    assert any(f.startswith("soc:") for f in campaign.check_soc(scen, more))
    # The energy oracle: a cell whose every term is known holds it (the RC pair charged at
    # the end); a heat figure 1 % off is caught.
    cell = {"capacity_Ah": 5.0, "ocv_V": {"x": [0.0, 0.5, 1.0], "y": [3.0, 3.7, 4.2]},
            "r0_ohm": {"x": [0.0, 1.0], "y": [0.012, 0.010]}, "rc_pairs": [{"r_ohm": 0.006, "tau_s": 30.0}],
            "v_min_V": 2.8, "v_max_V": 4.25}
    scen = {"pack": {"series": 3, "parallel": 2, "cell": cell}}
    hot = packsim.run({**scen, "load": {"current_A": 15.0}, "run": {"duration_s": 60.0},
                       "bms": {"tick_ms": 100}, "output": {"interval_s": 1.0}})
    assert campaign.energy_balance(scen, hot)[2] > 1.0  # J in the RC pairs: the term is exercised
    assert campaign.check_energy(scen, hot) == []
    off = Tampered(hot)
    off.summary = dict(hot.summary, heat_Wh=1.01 * hot.summary["heat_Wh"])
    assert any(f.startswith("energy:") for f in campaign.check_energy(scen, off))
    other = packsim.run(yaml, seed=99)
    assert campaign.same_bytes(packsim.run(yaml), other) != ""


def test_the_record_oracles_can_fail():
    """Each summary figure the record oracles judge (scripts/campaign_record.py), made
    plausibly wrong, is caught; the run itself holds every one of them."""
    rec = _campaign().rec
    import numpy as np
    import packsim
    scen = {"pack": {"series": 3, "parallel": 2, "initial_soc": 0.4, "cell": {"preset": "ncr18650_3p1Ah"},
                     "spread": {"initial_soc_sd": 0.03}},
            "load": {"segments": [{"duration_s": 3.05, "current_A": 12.0}, {"duration_s": 2.0, "current_A": -3.0}]},
            "hardware": {"balancing": {"resistor_ohm": 10.0}},
            "bms": {"tick_ms": 100, "balancing": {"when": "always", "start_delta_mV": 2, "stop_delta_mV": 1,
                                                  "min_cell_V": 3.0}},
            "run": {"duration_s": 8.0}, "output": {"interval_s": 0.1}}
    r = packsim.run(scen)
    assert r.summary["balance_bled_Ah"] > 0 and r.summary["energy_stranded_Wh"] > 0  # the terms are exercised
    cells = rec.Cells(rec.cell_table(scen), 6)
    t = np.asarray(r["time_s"])
    busy = rec.busy_intervals(t, [3.05, 5.05])
    assert rec.check_groups(r, 3, 2) == []
    assert rec.check_cell_charge(r, cells, 3, 2, busy, cvode=True) == []
    assert rec.check_bled(r, busy) == [] and rec.check_energy_out(r, busy) == []
    assert rec.check_extremes(r) == [] and rec.check_trip(r, False) == [] and rec.check_stranded(r, cells) == []

    class Tampered:  # the run with some summary figures changed
        def __init__(self, **summary):
            self.events, self.summary = r.events, dict(r.summary, **summary)

        def __getitem__(self, key):
            return r[key]

        def keys(self):
            return r.keys()

    s = r.summary
    assert rec.check_cell_charge(Tampered(charge_delivered_Ah=s["charge_delivered_Ah"] * 1.01), cells, 3, 2,
                                 busy, cvode=True)
    assert rec.check_bled(Tampered(balance_bled_Ah=s["balance_bled_Ah"] * 1.1), busy)
    assert rec.check_energy_out(Tampered(energy_delivered_Wh=s["energy_delivered_Wh"] * 1.1), busy)
    assert rec.check_extremes(Tampered(min_cell=s["min_cell"] % 6 + 1))
    assert rec.check_extremes(Tampered(hottest_time_s=0.0))
    assert rec.check_trip(Tampered(tripped=1, trip_time_s=2.0, trip_reason="cell_undervoltage"), False)
    assert rec.check_stranded(Tampered(energy_stranded_Wh=s["energy_stranded_Wh"] * 1.01), cells)
    assert rec.check_stranded(Tampered(limit_cell=s["limit_cell"] % 6 + 1), cells)
    assert rec.check_states(r) == []
    assert rec.check_states(Tampered(final_soc_min=s["final_soc_min"] - 1e-6))
    assert rec.check_states(Tampered(balance_started_s=s["balance_started_s"] + 0.1))
