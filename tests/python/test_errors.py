"""C++ errors arrive as Python exceptions with the same message and their parts."""
from __future__ import annotations

import pickle

import pytest

import packsim


def test_scenario_error_in_text_carries_position(simple_yaml):
    bad = simple_yaml.replace("capacity_Ah: 2.0", "capcity_Ah: 2.0")
    with pytest.raises(packsim.ScenarioError) as ei:
        packsim.run(bad)
    e = ei.value
    assert isinstance(e, ValueError)
    assert e.file == "<string>"
    assert (e.line, e.column) == (7, 5)
    assert e.field == "pack.cell.capcity_Ah"
    assert e.message == "unknown key; did you mean 'capacity_Ah'?"
    assert str(e) == "<string>:7:5: pack.cell.capcity_Ah: unknown key; did you mean 'capacity_Ah'?"


def test_scenario_error_in_file_names_the_file(tmp_path, simple_yaml):
    p = tmp_path / "bad.yaml"
    p.write_text(simple_yaml.replace("initial_soc: 0.9", "initial_soc: 1.9"))
    with pytest.raises(packsim.ScenarioError) as ei:
        packsim.run(p)
    e = ei.value
    assert e.file == str(p) and e.line == 5 and e.field == "pack.initial_soc"
    assert "out of range" in e.message and str(e).startswith(f"{p}:5:")


def test_override_errors_name_the_override(simple_yaml):
    with pytest.raises(packsim.ScenarioError) as ei:
        packsim.run(simple_yaml, {"pack.cell.capacity_ah": 3})
    e = ei.value
    assert e.field == "pack.cell.capacity_ah" and e.line == 0
    assert "did you mean 'capacity_Ah'?" in e.message and "after override pack.cell.capacity_ah = 3" in e.message
    with pytest.raises(packsim.ScenarioError, match="pack.series is a single value, not a mapping"):
        packsim.run(simple_yaml, {"pack.series.count": 3})


def test_dict_scenario_errors_name_the_value_as_given_not_as_an_override():
    """A dict is the user's scenario: its keys travel as overrides on an empty one, but
    an error on one names it as given ("after override" is a word the user never used)."""
    with pytest.raises(packsim.ScenarioError) as ei:
        packsim.run({"pack": {"series": 0, "cell": {"preset": "lipo_5Ah"}}, "load": {"current_A": 1}})
    e = ei.value
    assert e.file == "<dict>" and e.field == "pack.series"
    assert e.message.endswith("(given as pack.series = 0)") and "override" not in e.message, e.message
    with pytest.raises(packsim.ScenarioError, match=r"did you mean 'load'\? \(given as lod.current_A = 1\)"):
        packsim.run({"pack": {"series": 2, "cell": {"preset": "lipo_5Ah"}}, "lod": {"current_A": 1}})


def test_a_dict_scenarios_fault_is_named_by_its_place_in_the_list_not_a_line():
    """A fault given in a dict has no file line: the end-of-run event names faults[N]."""
    r = packsim.run({"pack": {"series": 2, "cell": {"preset": "lipo_5Ah"}}, "load": {"current_A": 1},
                     "run": {"duration_s": 20},
                     "faults": [{"kind": "key_off", "at_s": 2}, {"kind": "welded_relay", "at_s": 5}]})
    details = [e["detail"] for e in r.events if e["kind"] == "fault_no_effect"]
    assert len(details) == 1 and details[0].startswith("welded_relay (faults[1], given in the dict, active from 5.000 s"), details


def test_scenario_error_pickles_with_its_attributes(simple_yaml):
    with pytest.raises(packsim.ScenarioError) as ei:
        packsim.run(simple_yaml.replace("r0_ohm: 0.02", "r0_ohm: low"))
    e2 = pickle.loads(pickle.dumps(ei.value))
    assert (e2.file, e2.line, e2.column, e2.field, e2.message) == \
        (ei.value.file, ei.value.line, ei.value.column, ei.value.field, ei.value.message)
    assert str(e2) == str(ei.value)


def test_other_cpp_errors_are_runtime_errors(simple_yaml, tmp_path):
    r = packsim.run(simple_yaml)
    blocker = tmp_path / "file"
    blocker.write_text("x")
    # The C++ writer cannot create a folder where a file is: its own message, as RuntimeError.
    with pytest.raises(RuntimeError) as ei:
        r.save(blocker / "sub" / "r.h5")
    assert not isinstance(ei.value, packsim.ScenarioError)
    assert str(ei.value)


def test_bad_argument_types():
    with pytest.raises(TypeError, match="scenario must be"):
        packsim.run(42)
    with pytest.raises(TypeError, match="overrides must be a mapping"):
        packsim.run("x: 1\n", [("a", 1)])
    with pytest.raises(TypeError, match="keys must be str"):
        packsim.run("x: 1\n", {1: 2})
    with pytest.raises(TypeError, match="seed must be an int"):
        packsim.run("x: 1\n", seed="7")
    with pytest.raises(TypeError, match="cannot use a"):
        packsim.run("x: 1\n", {"pack.series": object()})
    with pytest.raises(ValueError, match=r"seed must be in \[0, 2147483647\] \(a scenario's seed: range\), got -1"):
        packsim.run("x: 1\n", seed=-1)
    # Was "seed must be >= 0, got 18446744073709551616": a message that named no upper bound.
    with pytest.raises(ValueError, match=r"seed must be in \[0, 2147483647\] \(a scenario's seed: range\), got 2147483648"):
        packsim.run("x: 1\n", seed=2**31)
    with pytest.raises(FileNotFoundError):
        packsim.run("no_such_scenario.yaml")


def test_a_nan_or_infinity_names_the_field_and_its_range(simple_yaml, tmp_path):
    """A NaN from a notebook (a failed fit, an empty mean) was "override
    'pack.cell.capacity_Ah': nan is not a finite number": the key, but not what it takes.
    It goes to the loader as YAML's .nan, which names the field and its allowed range,
    as the same value in a file does (the CLI's text)."""
    import numpy as np
    with pytest.raises(packsim.ScenarioError) as ei:
        packsim.run(simple_yaml, {"pack.cell.capacity_Ah": float("nan")})
    assert ei.value.field == "pack.cell.capacity_Ah"
    assert ei.value.message.startswith("expected a finite number, got '.nan'; allowed (0, 10000]")
    with pytest.raises(packsim.ScenarioError, match=r"pack.initial_soc: expected a finite number, got '-.inf'; "
                                                    r"allowed \[0, 1\]"):
        packsim.run(simple_yaml, pack={"initial_soc": np.float64(-np.inf)})
    with pytest.raises(packsim.ScenarioError, match=r"ambient.temp_C: expected a finite number, got '.inf'; allowed"):
        packsim.run(simple_yaml, {"ambient.temp_C": float("inf")})
    # Inside a list of mappings: the same message for its element.
    with pytest.raises(packsim.ScenarioError, match=r"rc_pairs\[0\].r_ohm: expected a finite number, got '.nan'"):
        packsim.run(simple_yaml, {"pack.cell.rc_pairs": [{"r_ohm": float("nan"), "tau_s": 20.0}]})
    # A sweep's varied value: the sweep's error at its line, before any case runs.
    base = tmp_path / "base.yaml"
    base.write_text(simple_yaml)
    with pytest.raises(packsim.ScenarioError, match=r"expected a finite number, got '.nan'; allowed \[0, 1\]"):
        packsim.batch({"base": str(base), "grid": {"pack.initial_soc": [0.5, float("nan")]}},
                      output_dir=str(tmp_path / "out"))
    assert not (tmp_path / "out").exists()
