"""Overrides change exactly what they name, in every spelling the API accepts."""
from __future__ import annotations

import numpy as np
import pytest

import packsim


def _final_soc(r: packsim.Result) -> np.ndarray:
    return r["truth/cell_soc"][-1]


def test_capacity_override_changes_final_soc_as_coulomb_counting_says(simple_yaml):
    # Constant 2 A from the relay contact closing (where the firmware wrote the pin, after
    # its tick's bus time) to the end, no trip: SOC_end = SOC_0 - I (t_end - t_close) / (3600 C).
    for cap in (2.0, 3.0, 4.5):
        r = packsim.run(simple_yaml, {"pack.cell.capacity_Ah": cap})
        assert not r.summary["tripped"]
        t_close = next(e["time_s"] for e in r.events if e["kind"] == "relay_contact" and e["detail"] == "closed")
        t_end = r.time_s[-1]
        assert t_close < 1.0 and t_end == pytest.approx(600.0, abs=1.0)
        expected = 0.9 - 2.0 * (t_end - t_close) / (3600.0 * cap)
        np.testing.assert_allclose(_final_soc(r), expected, rtol=0, atol=1e-8)
        assert f"capacity_Ah: {cap}" in r.scenario_yaml


def test_nested_dotted_and_keyword_spellings_agree(simple_yaml):
    a = packsim.run(simple_yaml, {"pack": {"cell": {"capacity_Ah": 3.0}}, "load": {"current_A": 1.0}})
    b = packsim.run(simple_yaml, {"pack.cell.capacity_Ah": 3.0, "load.current_A": 1.0})
    c = packsim.run(simple_yaml, pack={"cell": {"capacity_Ah": 3.0}}, load={"current_A": 1.0})
    d = packsim.run(simple_yaml, {"pack.cell.capacity_Ah": 9.0}, **{"pack.cell.capacity_Ah": 3.0, "load.current_A": 1.0})
    for other in (b, c, d):
        assert other.scenario_yaml == a.scenario_yaml
        np.testing.assert_array_equal(other["truth/cell_soc"], a["truth/cell_soc"])
    np.testing.assert_allclose(_final_soc(a), 0.9 - (a.time_s[-1] - 0.02) / (3600.0 * 3.0), atol=1e-6)


def test_list_index_and_numpy_values(simple_yaml):
    y = simple_yaml.replace("    r0_ohm: 0.02\n", "    r0_ohm: 0.02\n    rc_pairs: [{r_ohm: 0.01, tau_s: 20}]\n")
    ref = packsim.run(y)
    r = packsim.run(y, {"pack.cell.rc_pairs.0.r_ohm": np.float64(0.05)})
    assert "r_ohm: 0.05" in r.scenario_yaml
    # After 30 time constants at 2 A the RC branch sits at I*R: 0.04 ohm more is 80 mV less.
    dv = ref["truth/cell_voltage_V"][-1] - r["truth/cell_voltage_V"][-1]
    np.testing.assert_allclose(dv, 2.0 * 0.04, atol=1e-6)
    half = packsim.run(y, {"pack.initial_soc": np.float32(0.5)})
    assert half["truth/cell_soc"][0, 0] == pytest.approx(0.5, abs=1e-9)


def test_a_zero_dimensional_array_is_its_value(simple_yaml):
    """A notebook's scalar often comes as a 0-d array (``arr.mean(keepdims=False)`` of an
    xarray, ``np.asarray(x)``): it was "TypeError: 'float' object is not iterable", naming
    no argument. It is the number it holds, as a NumPy scalar is."""
    text = packsim.apply_overrides(simple_yaml, {"pack.initial_soc": np.array(0.5)})
    assert text == packsim.apply_overrides(simple_yaml, {"pack.initial_soc": 0.5})
    with pytest.raises(packsim.ScenarioError, match=r"pack.initial_soc: expected a finite number, got '.nan'"):
        packsim.run(simple_yaml, {"pack.initial_soc": np.array(np.nan)})


def test_floats_arrive_exactly(simple_yaml):
    v = 0.1 + 0.2  # 0.30000000000000004: repr round-trips, str() would not in older Pythons
    text = packsim.apply_overrides(simple_yaml, {"pack.cell.r0_ohm": v})
    assert "r0_ohm: 0.30000000000000004" in text


def test_dict_scenario_equals_yaml_scenario(simple_yaml):
    import yaml
    d = yaml.safe_load(simple_yaml)
    a = packsim.run(d)
    b = packsim.run(simple_yaml)
    np.testing.assert_array_equal(a["truth/cell_voltage_V"], b["truth/cell_voltage_V"])
    np.testing.assert_array_equal(a["measured/cell_voltage_mV"], b["measured/cell_voltage_mV"])


def test_seed_keyword_is_the_cli_seed(simple_yaml):
    a = packsim.run(simple_yaml, seed=11)
    b = packsim.run(simple_yaml, {"seed": 11})
    c = packsim.run(simple_yaml)
    assert a.seed == b.seed == 11 and c.seed == 5
    assert a.scenario_yaml == simple_yaml  # seed= leaves the stored text as written
    np.testing.assert_array_equal(a["measured/cell_voltage_mV"], b["measured/cell_voltage_mV"])
    assert not np.array_equal(a["measured/cell_voltage_mV"], c["measured/cell_voltage_mV"])


def test_file_scenario_keeps_relative_csv_paths(default_scenario, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # the CSV is found next to the scenario, not in the cwd
    r = packsim.run(default_scenario, {"load.laps": 1})
    full = packsim.run(default_scenario, {"load.laps": 2})
    assert r.time_s[-1] < full.time_s[-1]
    assert r.summary["charge_delivered_Ah"] == pytest.approx(full.summary["charge_delivered_Ah"] / 2, rel=0.05)
