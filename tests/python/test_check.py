"""packsim.check mirrors `packsim check`: the same verdicts and text for the same files,
and fault latencies that are exactly the run's events and respect the configured debounce."""
from __future__ import annotations

import subprocess
from pathlib import Path

import pytest

import packsim

TICK_S = 0.010        # bms.tick_ms default
DEBOUNCE_S = 0.200    # set below for overcurrent_discharge

OVERCURRENT = """\
bms:
  protections:
    overcurrent_discharge: {threshold_A: 30, delay_ms: 200}
faults:
  - {kind: overcurrent, current_A: 40, at_s: 100, duration_s: 5}
"""


@pytest.fixture
def scenario_dir(tmp_path, simple_yaml) -> Path:
    d = tmp_path / "scen"
    (d / "profiles").mkdir(parents=True)
    (d / "a_ok.yaml").write_text(simple_yaml + "expect: {no_trip: true, min_cell_V_above: 3.0}\n")
    (d / "b_overcurrent.yaml").write_text(
        simple_yaml + OVERCURRENT + "expect:\n  trip_reason: overcurrent_discharge\n  trip_within_s: [100.2, 100.25]\n")
    (d / "c_wrong_expectation.yaml").write_text(simple_yaml + "expect: {trip_reason: overtemperature}\n")
    (d / "d_bad.yaml").write_text(simple_yaml.replace("r0_ohm", "r0_ohms"))
    (d / "profiles" / "not_a_scenario.yaml").write_text("time_s: [0]\n")  # skipped, as by the CLI
    return d


def test_same_text_and_verdict_as_the_cli(cli, scenario_dir):
    done = subprocess.run([str(cli), "check", str(scenario_dir)], capture_output=True, text=True)
    report = packsim.check(scenario_dir, threads=2)
    assert str(report) == done.stdout
    assert done.returncode == 1 and not report.passed and not report
    assert [o.status for o in report] == ["PASS", "PASS", "FAIL", "ERROR"]
    assert (report.n_passed, report.n_failed) == (2, 2)
    assert [Path(o.name).name for o in report.failed] == ["c_wrong_expectation.yaml", "d_bad.yaml"]
    bad = report[3]
    assert "r0_ohms" in bad.error and "did you mean 'r0_ohm'?" in bad.error
    assert report[2].failures == ("expected a trip on overtemperature, but there was none",)


def test_latencies_are_the_runs_events_and_respect_the_debounce(scenario_dir):
    path = scenario_dir / "b_overcurrent.yaml"
    outcome = packsim.check(path)[0]
    assert outcome.passed and outcome.verdict.startswith("trip at")
    (lat,) = outcome.latencies
    # Independently, from the events of the same run:
    r = packsim.run(path)
    ev = r.events
    inj = next(e for e in ev if e["kind"] == "fault_injected")
    det = next(e for e in ev if e["kind"] == "fault_active" and e["time_s"] >= inj["time_s"])
    # The contact opens where the firmware wrote the pin: after the command's tick, by the
    # control step's bus time (docs/firmware.md, Scheduling).
    command = next(e for e in ev if e["kind"] == "relay" and e["detail"] == "open" and e["time_s"] >= inj["time_s"])
    opened = next(e for e in ev if e["kind"] == "relay_contact" and e["detail"] == "opened" and e["time_s"] >= inj["time_s"])
    assert command["time_s"] <= opened["time_s"] < command["time_s"] + TICK_S
    assert lat.injected == inj["detail"] and lat.injected_at_s == inj["time_s"] == 100.0
    assert lat.detected_fault == det["detail"].split(":")[0] == "overcurrent_discharge"
    assert lat.detection_latency_s == det["time_s"] - inj["time_s"]
    assert lat.relay_open_latency_s == opened["time_s"] - inj["time_s"]
    # The BMS confirms after its 200 ms debounce, within one tick of sampling.
    assert DEBOUNCE_S - 1e-9 <= lat.detection_latency_s <= DEBOUNCE_S + TICK_S + 1e-9
    assert lat.relay_open_latency_s >= lat.detection_latency_s
    assert lat.line == f"{inj['detail']} @100.000 s: overcurrent_discharge after " \
                       f"{lat.detection_latency_s:.3f} s, relay open after {lat.relay_open_latency_s:.3f} s"


def test_no_fault_means_no_latency(simple_yaml):
    # The fault ends before the BMS debounce: injected, never detected, relay stays closed.
    y = simple_yaml + OVERCURRENT.replace("duration_s: 5", "duration_s: 0.1")
    (lat,) = packsim.check(y)[0].latencies
    assert lat.detected_fault is None and lat.detection_latency_s is None and lat.relay_open_latency_s is None
    assert lat.line.endswith("no BMS fault it can cause, relay not opened")


def test_result_text_dict_and_overrides(simple_yaml):
    import yaml
    y = simple_yaml + "expect: {no_trip: true}\n"
    r = packsim.run(y)
    by_result = packsim.check(r)[0]
    by_text = packsim.check(y)[0]
    by_dict = packsim.check(yaml.safe_load(y))[0]
    assert by_result.passed and by_result == by_text
    assert by_dict.passed and by_dict.verdict == by_text.verdict
    # An override that adds a fault turns the verdict, and names the trip.
    faults = yaml.safe_load(OVERCURRENT)
    tripped = packsim.check(y, faults)[0]
    assert not tripped.passed
    assert tripped.failures[0].startswith("expected no trip, but the BMS tripped at 100.2")
    assert "the relay contact opened at 100.2" in tripped.failures[0]
    assert "overcurrent_discharge" in tripped.failures[0]
    # A bad scenario in text is an error outcome, as for a file.
    err = packsim.check(y.replace("series: 3", "series: -3"))[0]
    assert err.status == "ERROR" and "pack.series" in err.error and err.name == "<string>"


def test_file_with_overrides_and_seed(scenario_dir):
    path = scenario_dir / "a_ok.yaml"
    plain = packsim.check(path)[0]
    seeded = packsim.check(path, seed=3)[0]
    assert plain.passed and seeded.passed and seeded.name == plain.name == str(path)
    low = packsim.check([path], {"expect.min_cell_V_above": 3.99})[0]
    assert not low.passed and low.failures[0].startswith("lowest cell")


def test_threads_do_not_change_the_outcomes(scenario_dir):
    assert packsim.check(scenario_dir, threads=1).outcomes == packsim.check(scenario_dir, threads=3).outcomes


def test_tables(scenario_dir):
    pytest.importorskip("pandas")
    report = packsim.check(scenario_dir)
    df = report.to_dataframe()
    assert list(df.status) == ["PASS", "PASS", "FAIL", "ERROR"]
    lat = report.latencies_dataframe()
    assert len(lat) == 1 and lat.detected_fault[0] == "overcurrent_discharge"


def test_bad_arguments(tmp_path, simple_yaml):
    with pytest.raises(TypeError, match="scenarios must be"):
        packsim.check(42)
    with pytest.raises(TypeError, match="scenario paths must be"):
        packsim.check([str(tmp_path), 3])
    with pytest.raises(ValueError, match="no scenario files found"):
        packsim.check(tmp_path)
    with pytest.raises(TypeError, match="threads must be an int"):
        packsim.check(simple_yaml, threads=1.5)
    with pytest.raises(ValueError, match="threads must be >= 1"):
        packsim.check(tmp_path, threads=0)
    with pytest.raises(TypeError, match="seed must be an int"):
        packsim.check(simple_yaml, seed="1")
    r = packsim.run(simple_yaml)
    saved = tmp_path / "r.h5"
    r.save(saved)
    with pytest.raises(ValueError, match="only a Result of packsim.run"):
        packsim.check(packsim.load(saved))
    with pytest.raises(ValueError, match="judged as it ran"):
        packsim.check(r, seed=2)


def test_scenario_without_expect_is_ran_not_pass(cli, simple_yaml, tmp_path):
    # The same verdict and text from the CLI and from Python: "RAN", nothing to check.
    f = tmp_path / "no_expect.yaml"
    f.write_text(simple_yaml)
    done = subprocess.run([str(cli), "check", str(f)], capture_output=True, text=True)
    report = packsim.check(f)
    assert done.returncode == 0 and str(report) == done.stdout
    (o,) = report
    assert o.status == "RAN" and o.nothing_to_check and o.verdict.startswith("ran, nothing to check")
    assert (report.n_passed, report.n_failed, report.n_unchecked) == (0, 0, 1)
    assert done.stdout.endswith("0 passed, 0 failed, 1 ran with nothing to check\n")
