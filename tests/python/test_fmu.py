"""`packsim fmu`: the FMI 2.0 co-simulation FMU checked with fmpy (its validator and its
simulator) against `packsim run` of the same scenario (docs/fmu.md)."""
from __future__ import annotations

import os
import subprocess
import zipfile
from pathlib import Path

import h5py

import packsim
import numpy as np
import pytest

fmpy = pytest.importorskip("fmpy")
from fmpy.validation import validate_fmu  # noqa: E402

# A 6s bench pack on a step profile from a CSV (breakpoints on output points), with a
# cell preset: both are files the FMU must carry in resources/.
PROFILE = "time_s,current_A\n0,2.0\n30,6.0\n60,-1.5\n90,4.0\n120,4.0\n"
BREAKPOINTS_S = [30.0, 60.0, 90.0]
SCENARIO = """\
name: fmu_bench
seed: 11
pack:
  series: 6
  initial_soc: 0.8
  cell: {preset: ncr18650_3p1Ah}
hardware:
  thermistors: {at_groups: [2, 5]}
bms:
  tick_ms: 100
  protections:
    overcurrent_discharge: {threshold_A: 10, delay_ms: 200}
load: {csv: profiles/steps.csv}
run: {duration_s: 110}
output: {interval_s: 1.0}
"""
# The same pack, 20 A injected on top of the load at 40 s: an over-current trip.
FAULT = SCENARIO.replace("name: fmu_bench", "name: fmu_overcurrent").replace(
    "output: {interval_s: 1.0}", "output: {interval_s: 0.1}\nfaults:\n  - {kind: overcurrent, current_A: 20, at_s: 40.0, duration_s: 5}"
).replace("run: {duration_s: 110}", "run: {duration_s: 60, stop_after_trip_s: 5}")

OUTPUTS = ["pack_voltage", "pack_current", "cell_voltage[1]", "soc_true", "soc_bms", "relay_closed", "tripped",
           "fault_latched", "bms_state"]


def _write(tmp: Path, name: str, text: str) -> Path:
    (tmp / "profiles").mkdir(exist_ok=True)
    (tmp / "profiles" / "steps.csv").write_text(PROFILE)
    p = tmp / f"{name}.yaml"
    p.write_text(text)
    return p


def _fmu(cli: Path, scenario: Path, out: Path) -> Path:
    subprocess.run([str(cli), "fmu", str(scenario), "-o", str(out), "-q"], check=True, capture_output=True, text=True)
    return out


def _run(cli: Path, scenario: Path, out: Path):
    """The scenario run by packsim (the CLI's file is checked to be written; the arrays
    compared are packsim.run's, the recording itself: the file keeps float channels to
    their stated resolution, docs/results.md)."""
    subprocess.run([str(cli), "run", str(scenario), "-o", str(out), "-q"], check=True)
    assert out.exists()
    return packsim.run(str(scenario))


def _simulate(fmu: Path, stop_s: float, interval_s: float, signal=None):
    return fmpy.simulate_fmu(str(fmu), stop_time=stop_s, output_interval=interval_s, output=OUTPUTS, input=signal)


@pytest.fixture(scope="module")
def bench(cli, tmp_path_factory):
    tmp = tmp_path_factory.mktemp("fmu")
    scenario = _write(tmp, "fmu_bench", SCENARIO)
    fmu = _fmu(cli, scenario, tmp / "bench.fmu")
    return scenario, fmu, _run(cli, scenario, tmp / "bench.h5")


def _truth(h5: h5py.File):
    return {
        "time": h5["time_s"][()],
        "pack_voltage": h5["truth/pack_voltage_V"][()],
        "pack_current": h5["truth/pack_current_A"][()],
        "cell_voltage[1]": h5["truth/cell_voltage_V"][()][:, 0],
        "soc_true": h5["truth/soc_mean"][()],
        "soc_bms": h5["bms/soc_estimate_permille"][()] * 1e-3,
        "relay_closed": h5["hardware/relay_closed"][()],
    }


def test_fmu_passes_fmpy_validation(bench):
    _, fmu, _ = bench
    assert validate_fmu(str(fmu)) == []
    names = set(zipfile.ZipFile(fmu).namelist())
    assert {"modelDescription.xml", "binaries/linux64/packsim_fmu.so", "resources/scenario.yaml",
            "resources/profiles/steps.csv", "resources/cells/ncr18650_3p1Ah.yaml"} <= names


def test_fmu_without_inputs_reproduces_packsim_run(bench):
    _, fmu, h5 = bench
    ref = _truth(h5)
    res = _simulate(fmu, 110.0, 1.0)
    assert np.array_equal(res["time"], ref["time"])
    # The same loop, ticks and solver calls: equal to the last bit.
    for k in ("pack_voltage", "pack_current", "cell_voltage[1]", "soc_true", "soc_bms"):
        assert np.max(np.abs(res[k] - ref[k])) == 0.0, k
    assert np.array_equal(res["relay_closed"].astype(int), ref["relay_closed"].astype(int))


def test_fmu_driven_by_the_load_signal_matches(bench):
    """The CSV's steps as an fmpy input signal (a discontinuity is two rows at one time)."""
    _, fmu, h5 = bench
    ref = _truth(h5)
    t, i = [0.0], [2.0]
    for tb, ib in zip(BREAKPOINTS_S, [6.0, -1.5, 4.0]):
        t += [tb, tb]
        i += [i[-1], ib]
    t.append(120.0)
    i.append(i[-1])
    signal = np.array(list(zip(t, i)), dtype=[("time", np.float64), ("load_current", np.float64)])
    res = _simulate(fmu, 110.0, 1.0, signal)
    # An input set at a communication point t acts on the plant from t; the outputs at t
    # were sampled before it was set, so at a step's own time they show the value before
    # the step. Everywhere else: solver tolerance.
    at_step = np.isin(ref["time"], BREAKPOINTS_S)
    # Measured: 9.5e-6 V pack, 1.6e-6 V cell, 9e-16 A, 4e-16 SOC (CVODE rtol 1e-6 with other stop times).
    for k, tol in (("pack_voltage", 5e-5), ("pack_current", 1e-12), ("cell_voltage[1]", 1e-5), ("soc_true", 1e-12)):
        err = np.max(np.abs(res[k][~at_step] - ref[k][~at_step]))
        print(f"driven by the load signal: max |{k} error| = {err:.3g}")
        assert err <= tol, (k, err)
    assert np.array_equal(res["pack_current"][at_step], ref["pack_current"][np.flatnonzero(at_step) - 1])
    assert np.array_equal(res["relay_closed"].astype(int), ref["relay_closed"].astype(int))


def test_fmu_trips_on_overcurrent_at_the_same_time(cli, tmp_path):
    scenario = _write(tmp_path, "fmu_overcurrent", FAULT)
    fmu = _fmu(cli, scenario, tmp_path / "oc.fmu")
    h5 = _run(cli, scenario, tmp_path / "oc.h5")
    t = h5["time_s"][()]
    relay = h5["hardware/relay_closed"][()]
    opened_s = t[np.flatnonzero((relay[:-1] == 1) & (relay[1:] == 0))[0] + 1]
    res = _simulate(fmu, 60.0, 0.1)
    fmu_opened_s = res["time"][np.flatnonzero(res["relay_closed"][:-1] & ~res["relay_closed"][1:])[0] + 1]
    assert fmu_opened_s == pytest.approx(opened_s, abs=1e-9)
    assert 40.2 <= opened_s <= 40.35  # the 200 ms debounce (+ a tick, relay release)
    tripped_s = res["time"][np.argmax(res["tripped"])]
    assert res["tripped"][-1] and tripped_s <= fmu_opened_s
    assert res["fault_latched"][-1] != 0
    # The FMU keeps running past the scenario's stop-after-trip: the importer's stop time rules.
    assert res["time"][-1] == pytest.approx(60.0)


def test_bad_scenario_fails_at_fmu_time(cli, tmp_path):
    bad = _write(tmp_path, "bad", SCENARIO.replace("series: 6", "sereis: 6"))
    out = tmp_path / "bad.fmu"
    done = subprocess.run([str(cli), "fmu", str(bad), "-o", str(out)], capture_output=True, text=True)
    assert done.returncode != 0
    assert "bad.yaml:" in done.stderr and "series" in done.stderr
    assert not out.exists() and list(tmp_path.glob("bad.fmu*")) == []
    # A reference run (`compare:`) cannot be part of an FMU: refused, naming the key.
    cold = Path(__file__).resolve().parents[2] / "scenarios" / "scooter_16s_lto_cold.yaml"
    done = subprocess.run([str(cli), "fmu", str(cold), "-o", str(out)], capture_output=True, text=True)
    assert done.returncode == 2 and "scooter_16s_lto_cold.yaml:" in done.stderr and "compare:" in done.stderr
    assert not out.exists()


def test_a_missing_fmu_library_is_a_failed_run_not_bad_input(cli, tmp_path):
    """The scenario is fine; the installation lacks the FMU library: exit 1 (a failed run,
    as the README defines it), naming the path looked at, and no archive left behind."""
    good = _write(tmp_path, "good", SCENARIO)
    out = tmp_path / "good.fmu"
    missing = tmp_path / "nowhere" / "packsim_fmu.so"
    done = subprocess.run([str(cli), "fmu", str(good), "-o", str(out)], capture_output=True, text=True,
                          env=dict(os.environ, PACKSIM_FMU_BINARY=str(missing)))
    assert done.returncode == 1, done.stderr
    assert str(missing) in done.stderr and "FMU library was not built" in done.stderr
    assert not out.exists() and list(tmp_path.glob("good.fmu*")) == []


def test_fmu_rejects_a_step_that_is_not_whole_ticks(bench):
    _, fmu, _ = bench
    messages = []
    with pytest.raises(Exception):
        fmpy.simulate_fmu(str(fmu), stop_time=1.0, output_interval=0.25,
                          logger=lambda *a: messages.append(str(a[-1])))
    assert any("whole number of BMS ticks" in str(m) for m in messages)


class _Slave:
    """One FMU instance driven by hand (fmpy's FMU2Slave), one communication step at a time."""

    def __init__(self, fmu: Path, unzipped: str, name: str):
        self.md = fmpy.read_model_description(str(fmu))
        self.vr = {v.name: v.valueReference for v in self.md.modelVariables}
        self.fmu = fmpy.fmi2.FMU2Slave(guid=self.md.guid, unzipDirectory=unzipped,
                                       modelIdentifier=self.md.coSimulation.modelIdentifier, instanceName=name)
        self.fmu.instantiate()
        self.fmu.setupExperiment(startTime=0.0)
        self.fmu.enterInitializationMode()
        self.t = 0.0

    def start(self):
        self.fmu.exitInitializationMode()

    def real(self, name: str) -> float:
        return self.fmu.getReal([self.vr[name]])[0]

    def boolean(self, name: str) -> bool:
        return bool(self.fmu.getBoolean([self.vr[name]])[0])

    def step(self, h: float):
        self.fmu.doStep(currentCommunicationPoint=self.t, communicationStepSize=h)
        self.t = round(self.t + h, 9)

    def close(self):
        self.fmu.terminate()
        self.fmu.freeInstance()


def test_two_instances_in_one_process_are_independent(bench, cli, tmp_path):
    """Instance A alone reproduces `packsim run` while instance B, in the same library,
    runs on inputs; B reproduces `packsim run` of the scenario that has those values
    (a constant 3 A load, 45 degC ambient) although its own scenario has neither."""
    scenario, fmu, h5 = bench
    ref_a = _truth(h5)
    other = _write(tmp_path, "other", SCENARIO.replace("load: {csv: profiles/steps.csv}",
                                                       "load: {current_A: 3.0}\nambient: {temp_C: 45}"))
    ref_b = _truth(_run(cli, other, tmp_path / "other.h5"))
    unzipped = fmpy.extract(str(fmu))
    a, b = _Slave(fmu, unzipped, "a"), _Slave(fmu, unzipped, "b")
    b.fmu.setReal([b.vr["load_current"], b.vr["ambient_temperature"]], [3.0, 45.0 + 273.15])
    a.start()
    b.start()
    va, vb, tb = [a.real("pack_voltage")], [b.real("pack_voltage")], [b.real("cell_temperature[1]")]
    for _ in range(110):
        a.step(1.0)
        b.step(1.0)
        va.append(a.real("pack_voltage"))
        vb.append(b.real("pack_voltage"))
        tb.append(b.real("cell_temperature[1]"))
    a.close()
    b.close()
    assert np.array_equal(np.array(va), ref_a["pack_voltage"])
    assert np.max(np.abs(np.array(vb) - ref_b["pack_voltage"])) <= 1e-9
    temp_ref = packsim.run(str(other))["truth/cell_temp_C"][:, 0] + 273.15
    assert np.max(np.abs(np.array(tb) - temp_ref)) <= 1e-9
    assert tb[-1] > tb[0]  # warming towards 45 degC


def test_estop_input_opens_the_relay_one_tick_after_it_is_set(bench, cli, tmp_path):
    """Pulling the internal E-switch through the input at t = 20 s does what the scripted
    E-switch fault at 20 s does, one BMS tick later: the tick at 20 s ran before the input
    was set (the FMU's outputs at 20 s were read then)."""
    _, fmu, _ = bench
    scripted = _write(tmp_path, "estop", SCENARIO.replace("output: {interval_s: 1.0}", "output: {interval_s: 0.1}\n"
                                                           "faults:\n  - {kind: estop, switch: internal, at_s: 20}")
                      .replace("run: {duration_s: 110}", "run: {duration_s: 25}"))
    h5 = _run(cli, scripted, tmp_path / "estop.h5")
    t_ref = h5["time_s"][()]
    relay_ref = h5["hardware/relay_closed"][()]
    opened_ref = t_ref[np.flatnonzero((relay_ref[:-1] == 1) & (relay_ref[1:] == 0))[0] + 1]
    s = _Slave(fmu, fmpy.extract(str(fmu)), "estop")
    s.start()
    opened = None
    while s.t < 25.0 and opened is None:
        if s.t == 20.0:
            s.fmu.setBoolean([s.vr["estop_internal"]], [True])
        s.step(0.1)
        if s.t > 1.0 and not s.boolean("relay_closed"):
            opened = s.t
    s.close()
    assert 20.0 <= opened_ref <= 20.1
    assert opened == pytest.approx(opened_ref + 0.1, abs=1e-9)


def test_the_wrong_load_input_and_a_bad_ambient_are_clean_errors(bench):
    _, fmu, _ = bench
    for start, expect in (({"load_power": 100.0}, "this scenario's load is a current; set load_current"),
                          ({"ambient_temperature": 20.0}, "outside")):
        messages = []
        with pytest.raises(Exception):
            fmpy.simulate_fmu(str(fmu), stop_time=1.0, output_interval=0.1, start_values=start,
                              logger=lambda *a: messages.append(str(a[-1])))
        assert any(expect in m for m in messages), messages


def test_docs_list_every_variable_of_the_model_description(bench):
    """docs/fmu.md's table against the FMU's variables (per-cell rows as `name[i]`)."""
    import re

    _, fmu, _ = bench
    md = fmpy.read_model_description(str(fmu))
    actual = {}
    for v in md.modelVariables:
        name = re.sub(r"\[\d+\]$", "[i]", v.name)
        actual[name] = (v.causality, v.type, v.unit or "")
    doc = (Path(__file__).resolve().parents[2] / "docs" / "fmu.md").read_text()
    rows = re.findall(r"^\| `([^`]+)` \| (input|output) \| (Real|Integer|Boolean) \|([^|]*)\|", doc, re.M)
    documented = {name: (caus, typ, unit.strip()) for name, caus, typ, unit in rows}
    assert documented == actual


def test_power_load_input_reproduces_the_scenario_with_that_power(cli, tmp_path):
    """A power-load scenario takes `load_power`: 80 W set from the start is `packsim run`
    of the same scenario with an 80 W load."""
    base = SCENARIO.replace("load: {csv: profiles/steps.csv}", "load: {power_W: 50}").replace(
        "run: {duration_s: 110}", "run: {duration_s: 30}")
    fmu = _fmu(cli, _write(tmp_path, "p50", base), tmp_path / "p50.fmu")
    ref = _truth(_run(cli, _write(tmp_path, "p80", base.replace("power_W: 50", "power_W: 80")), tmp_path / "p80.h5"))
    res = fmpy.simulate_fmu(str(fmu), stop_time=30.0, output_interval=1.0, output=OUTPUTS,
                            start_values={"load_power": 80.0})
    assert np.max(np.abs(res["pack_voltage"] - ref["pack_voltage"])) <= 1e-9
    closed = ref["relay_closed"] == 1
    assert np.allclose(res["pack_voltage"][closed] * res["pack_current"][closed], 80.0, rtol=1e-9)


def test_the_fmu_leaves_the_process_environment_alone(bench, tmp_path):
    """In a process without PACKSIM_SCENARIOS (a plain importer), an FMU with a cell preset
    loads it from its own resources and sets nothing its process's children would inherit."""
    import os
    import sys

    _, fmu, _ = bench
    env = {k: v for k, v in os.environ.items() if k != "PACKSIM_SCENARIOS"}
    script = ("import fmpy, subprocess\n"
              f"fmpy.simulate_fmu({str(fmu)!r}, stop_time=2.0, output_interval=1.0)\n"
              "print(subprocess.run(['sh', '-c', 'echo \"[$PACKSIM_SCENARIOS]\"'], capture_output=True, text=True).stdout)")
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, env=env, cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "[]"


def test_a_scenario_that_extends_another_is_packed_whole(cli, tmp_path):
    """The bundled E-switch fault extends the eco-marathon race (another folder, its lap
    CSV, a cell preset): the FMU carries the merged scenario and its files, and its first
    seconds are `packsim run`'s to solver tolerance."""
    src = Path(__file__).resolve().parents[2] / "scenarios" / "faults" / "a_estop.yaml"
    fmu = _fmu(cli, src, tmp_path / "estop.fmu")
    names = set(zipfile.ZipFile(fmu).namelist())
    assert {"resources/profiles/eco_marathon_lap.csv", "resources/cells/lipo_5Ah.yaml"} <= names
    assert validate_fmu(str(fmu)) == []
    short = tmp_path / "short.yaml"
    short.write_text(f"extends: {src}\nrun: {{duration_s: 5}}\n")
    ref = _truth(_run(cli, short, tmp_path / "short.h5"))
    res = _simulate(fmu, 5.0, 1.0)
    # Only CVODE's stop time differs (the 5 s run stops at its own end): 2e-8 V measured.
    for k, tol in (("pack_voltage", 1e-6), ("pack_current", 1e-9), ("cell_voltage[1]", 1e-6), ("soc_true", 1e-9)):
        assert np.max(np.abs(res[k] - ref[k])) <= tol, k
