"""A fitted cell out to BPX and PyBaMM's Thevenin model, and back (docs/fit.md,
"Interchange"). The cell is fitted on the DFN fixture (tests/data/dfn_ecker2015): HPPC and
C/20 at 0, 25 and 40 °C, so it carries Arrhenius laws and the OCV's temperature coefficient.
The PyBaMM tests need PyBaMM, which is not a test dependency: skipped without it (run them
in PyBaMM's own environment, see docs/fit.md)."""
from __future__ import annotations

import json
import warnings
from pathlib import Path

import numpy as np
import pytest

import packsim

pytest.importorskip("bpx", reason="BPX interchange needs the bpx package (scripts/install-deps.sh)")

FIXTURE = Path(__file__).resolve().parents[1] / "data" / "dfn_ecker2015"


def _fit(**kw) -> packsim.FitResult:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", packsim.FitWarning)
        return packsim.fit([str(FIXTURE / f"{k}_{t}C.csv") for k in ("hppc", "c20") for t in (0, 25, 40)],
                           rc_pairs=2, smoothing=0.1, **kw)


@pytest.fixture(scope="module")
def joint():
    return _fit()


def _preset_body(yaml_text: str) -> list[str]:
    """The preset without its comments (which name the source)."""
    return [line.split("   #")[0] for line in yaml_text.splitlines() if not line.startswith("#")]


def test_bpx_round_trip_gives_the_same_cell(joint, tmp_path):
    assert joint.temperatures[0].docv_dT_V_per_K is not None and joint.temperatures[0].r0_K != 0
    path = tmp_path / "cell.bpx.json"
    joint.save_bpx(path)
    doc = json.loads(path.read_text())
    assert doc["Header"]["Model"] == "Partial"
    ecm = doc["Parameterisation"]["User-defined"]
    assert ecm["Number of RC elements"] == 2 and ecm["Tau2 [s]"] == joint.temperatures[0].rc_tau_s[1]
    back = packsim.from_bpx(path)
    assert back.params == joint.params                       # every number, bit for bit
    assert back.ocv_temps_C == joint.ocv_temps_C and back.temperature_law == "arrhenius"
    assert _preset_body(back.yaml) == _preset_body(joint.yaml)
    assert back.files == [] and "from " + str(path) in back.capacity_source


def test_bpx_round_trip_of_a_one_temperature_fit_with_rc_tables(tmp_path):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", packsim.FitWarning)
        f = packsim.fit([str(FIXTURE / "hppc_25C.csv"), str(FIXTURE / "c20_25C.csv")], rc_pairs=1,
                        rc_over_soc=True, smoothing=1.0)
    assert f.temperature_law == "none" and f.temperatures[0].rc_r_ohm.shape == (1, f.soc_grid.size)
    back = packsim.from_bpx(f.bpx())
    assert back.params == f.params and back.temperature_law == "none"


@pytest.mark.parametrize("change, message", [
    (lambda d: d["Parameterisation"]["User-defined"].pop("R0 [Ohm]"), "no equivalent circuit"),
    (lambda d: d["Parameterisation"]["User-defined"].pop("Tau2 [s]"), "User-defined has no 'Tau2 \\[s\\]'"),
    (lambda d: d["Parameterisation"]["User-defined"]["R0 [Ohm]"]["x"].pop(), "not a valid BPX document|its x differs"),
    (lambda d: d["Header"].pop("Model"), "not a valid BPX document"),
    (lambda d: d["Parameterisation"]["User-defined"].__setitem__("Number of RC elements", 7), "not an integer in 0..4"),
    (lambda d: d["Parameterisation"]["User-defined"].__setitem__("Number of RC elements", 1.5), "not an integer in 0..4"),
    (lambda d: d["Parameterisation"]["User-defined"]["R0 [Ohm]"]["y"].__setitem__(3, -0.01),
     "not a valid packsim cell: .*r0_ohm"),
    (lambda d: d["Parameterisation"]["User-defined"]["Open-circuit voltage [V]"]["y"].reverse(),
     "not a valid packsim cell: .*ocv_V"),
])
def test_bad_bpx_is_one_clear_error(joint, tmp_path, change, message):
    doc = joint.bpx()
    change(doc)
    path = tmp_path / "bad.json"
    path.write_text(json.dumps(doc))
    with pytest.raises(packsim.FitError, match=message):
        packsim.from_bpx(path)


def test_bpx_file_that_is_not_json(tmp_path):
    path = tmp_path / "bad.json"
    path.write_text('{"Header": \n oops')
    with pytest.raises(packsim.FitError, match=r"bad.json:2: not JSON"):
        packsim.from_bpx(path)


def test_a_fit_per_temperature_is_not_exported():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", packsim.FitWarning)
        f = packsim.fit([str(FIXTURE / f"hppc_{t}C.csv") for t in (0, 25)], rc_pairs=1, temperature_law="table",
                        capacity_Ah=0.171, smoothing=0.1)
    with pytest.raises(packsim.FitError, match="temperature_law table"):
        f.bpx()


# ---- PyBaMM (skipped where it is not installed) ----

def test_pybamm_round_trip_gives_the_same_cell(joint):
    pytest.importorskip("pybamm", reason="PyBaMM is not a test dependency")
    back = packsim.from_pybamm(joint.pybamm_parameters(), soc_grid=joint.soc_grid)
    g, h = joint.temperatures[0], back.temperatures[0]
    np.testing.assert_allclose(h.ocv_V, g.ocv_V, rtol=1e-12)
    np.testing.assert_allclose(h.r0, g.r0, rtol=1e-12)
    np.testing.assert_allclose(h.rc_r_ohm, g.rc_r_ohm, rtol=1e-12)
    np.testing.assert_allclose(h.rc_tau_s, g.rc_tau_s, rtol=1e-12)
    np.testing.assert_allclose([h.r0_K, *h.rc_r_K, *h.rc_tau_K], [g.r0_K, *g.rc_r_K, *g.rc_tau_K], rtol=1e-9)
    assert back.capacity_Ah == joint.capacity_Ah


@pytest.mark.parametrize("temp_C", [25.0, 40.0])
def test_pybamm_thevenin_runs_the_exported_cell_as_packsim_does(temp_C):
    """The exported parameters in PyBaMM's Thevenin model beside packsim's own cell
    equations (the plant's, packsim._packsim.simulate_cell) on the held-out drive cycle,
    isothermal at temp_C (the OCV's temperature coefficient left out: PyBaMM's OCV has none)."""
    pybamm = pytest.importorskip("pybamm", reason="PyBaMM is not a test dependency")
    from packsim._fit_ecm import held_current
    from packsim._packsim import simulate_cell
    f = _fit(ocv_temperature=False)
    data = np.loadtxt(FIXTURE / f"drive_{temp_C:g}C.csv", delimiter=",", comments="#", skiprows=3)
    t, i = data[:, 0], data[:, 1]
    temps = np.full(t.size, temp_C)
    from packsim._fit_interchange import PYBAMM_FULL_SOC   # PyBaMM's model will not start at SoC 1
    ours = simulate_cell(f.yaml, t, i, held_current(i), temps, PYBAMM_FULL_SOC)
    p = f.pybamm_parameters({"Cell thermal mass [J/K]": 1e12, "Initial temperature [K]": temp_C + 273.15,
                             "Ambient temperature [K]": temp_C + 273.15})
    # the current linear between the samples: its charge and RC response over each interval are
    # those of packsim's held mean (exactly where the current is constant; the steps last 1 ms)
    p["Current function [A]"] = pybamm.Interpolant(t, i, pybamm.t, interpolator="linear")
    model = pybamm.equivalent_circuit.Thevenin(options={"number of rc elements": f.rc_pairs})
    sim = pybamm.Simulation(model, parameter_values=p, solver=pybamm.IDAKLUSolver(rtol=1e-10, atol=1e-10))
    sol = sim.solve(t_eval=t, t_interp=t)
    theirs = sol["Voltage [V]"].entries
    err_mV = 1e3 * (theirs - ours)
    assert theirs.size == t.size
    print(f"PyBaMM Thevenin vs packsim at {temp_C:g} °C: max {np.max(np.abs(err_mV)) * 1e3:.2f} µV over {t.size} samples")
    assert np.max(np.abs(err_mV)) < 0.001, f"max {np.max(np.abs(err_mV)):.4f} mV"


def test_cli_writes_the_bpx_beside_the_preset(cli, tmp_path):
    import subprocess
    files = [str(FIXTURE / "hppc_25C.csv"), str(FIXTURE / "c20_25C.csv")]
    out, doc = tmp_path / "cell.yaml", tmp_path / "cell.bpx.json"
    p = subprocess.run([str(cli), "fit", *files, "-o", str(out), "--bpx", str(doc), "--smoothing", "0.1"],
                       capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    assert f"wrote {out} and {doc}" in p.stdout
    back = packsim.from_bpx(doc)
    assert _preset_body(back.yaml) == _preset_body(out.read_text())
    # a fit that cannot be exported writes nothing at all
    out2, doc2 = tmp_path / "t.yaml", tmp_path / "t.json"
    p = subprocess.run([str(cli), "fit", str(FIXTURE / "hppc_0C.csv"), str(FIXTURE / "hppc_25C.csv"), "-o", str(out2),
                        "--bpx", str(doc2), "--temperature-law", "table", "--capacity-Ah", "0.171", "--rc-pairs", "1"],
                       capture_output=True, text=True)
    assert p.returncode == 2 and "temperature_law table" in p.stderr
    assert not out2.exists() and not doc2.exists()
