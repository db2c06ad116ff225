"""Cell-test data from a physics model nobody here wrote, for the `packsim fit` validation
tests (tests/python/test_fit_dfn.py) and docs/fit.md: PyBaMM's DFN (Doyle-Fuller-Newman)
with a lumped thermal model and the published Ecker2015 parameter set (a 0.156 Ah Kokam
NMC/graphite pouch cell, Arrhenius kinetics and diffusion), as a lab would record it.

    python3 -m venv .venv-pybamm && .venv-pybamm/bin/pip install 'pybamm==26.*'
    .venv-pybamm/bin/python scripts/make_dfn_fixture.py tests/data/dfn_ecker2015
    .venv-pybamm/bin/python scripts/make_dfn_fixture.py /tmp/dfn-full --every-sample   # undecimated

The CSVs are cached in the repository: the tests never need PyBaMM (about
four minutes to regenerate on a busy two-core machine). Each test starts with the cell full and rested at its chamber temperature
(0, 25 and 40 °C); columns time_s,current_A,voltage_V,temp_C (positive current
discharges, temp_C the cell's lumped temperature), no added noise:

  training  hppc_{0,25,40}C   per 10 % of SOC a 10 s 1C discharge pulse, a 10 s 0.75C charge
                              pulse (not at full charge), 10 % of capacity at C/2 and a 1 h
                              rest; the tenth step to the cut-off
            c20_{0,25,40}C    C/20 to the cut-off, then a 1 h rest
  held out  cc_1C_{0,25,40}C  1C to the cut-off, then a 20 min rest
            drive_{0,25,40}C  12 minutes at 1C, then a drive cycle (0.8C mean, 3C peaks,
                              regenerative braking) to 2,400 s, then a 600 s rest

Recorded every second (C/20: every 10 s); a current step is recorded on both of its sides
(1 ms apart), as a cycler logs a step change. Then decimated to keep the repository small:
every sample next to a current change is kept, others only when the voltage has moved 2 mV,
the temperature 0.1 °C or 120 s have passed since the last kept one (30 s in the drive
cycle). The samples kept are the DFN's own (no interpolation), and the current between two
kept samples is constant, so the decimated file is the same test, sampled less often.
"""
from __future__ import annotations

import argparse
import os

import numpy as np
import pybamm

TEMPS_C = (0.0, 25.0, 40.0)
PARAMETER_SET = "Ecker2015"
DV_V, DT_C = 0.002, 0.1          # decimation: keep a sample when V or T moved this much
STEP_S = 1e-3                    # a current step is recorded on both sides, this far apart


def model_and_parameters(temp_C: float):
    model = pybamm.lithium_ion.DFN(options={"thermal": "lumped"})
    p = pybamm.ParameterValues(PARAMETER_SET)
    p.update({"Ambient temperature [K]": 273.15 + temp_C, "Initial temperature [K]": 273.15 + temp_C})
    return model, p


def drive_current(capacity_Ah: float) -> np.ndarray:
    """(time_s, current_A) rows of a 2,400 s drive cycle: accelerations, cruising, braking."""
    c = capacity_Ah
    # first 20 % of capacity at 1C: a full (or cold) cell cannot take the braking current
    pattern = [(10, 3.0), (30, 1.0), (5, -0.75), (15, 0.0), (8, 2.5), (40, 1.2), (6, -1.0), (20, 0.3),
               (12, 2.0), (25, 0.8), (4, -0.5), (25, 0.0)]
    t, rows = 720.0, [(0.0, c)]
    while t < 2400.0:
        for d, rate in pattern:
            rows.append((t, rate * c))
            t += d
    rows.append((t, 0.0))
    rows.append((t + 600.0, 0.0))
    return np.array(rows)


def _columns(sol) -> np.ndarray:
    t = sol["Time [s]"].entries
    i = sol["Current [A]"].entries
    v = sol["Voltage [V]"].entries
    temp = sol["X-averaged cell temperature [K]"].entries - 273.15
    return np.column_stack([t, i, v, temp])


def run_experiment(temp_C: float, steps: list, period: str = "1 second") -> np.ndarray:
    model, p = model_and_parameters(temp_C)
    sim = pybamm.Simulation(model, parameter_values=p, experiment=pybamm.Experiment(steps, period=period),
                            solver=pybamm.IDAKLUSolver())
    sol = sim.solve(initial_soc=1.0)
    # each step's solution, its first sample (the step's start, at the previous step's last
    # time) moved STEP_S later: the current step recorded on both of its sides
    parts = []
    for k, step in enumerate(sol.sub_solutions):
        rows = _columns(step)
        if k:
            rows = rows.copy()
            rows[0, 0] += STEP_S
        parts.append(rows)
    rows = np.concatenate(parts)
    keep = np.concatenate(([True], np.diff(rows[:, 0]) > 1e-6))
    return rows[keep]


def run_profile(temp_C: float, current: np.ndarray) -> np.ndarray:
    """A current profile held piecewise constant (PyBaMM's current is positive on discharge)."""
    model, p = model_and_parameters(temp_C)
    starts, values = current[:-1, 0], current[:-1, 1]
    ends = current[1:, 0]
    t_knots = np.column_stack([starts, ends - STEP_S]).ravel()  # steps, not ramps
    p["Current function [A]"] = pybamm.Interpolant(t_knots, np.repeat(values, 2), pybamm.t, interpolator="linear")
    end = float(current[-1, 0])
    t_out = np.union1d(np.arange(0.0, end + 0.5, 1.0), ends[:-1] - STEP_S)
    sim = pybamm.Simulation(model, parameter_values=p, solver=pybamm.IDAKLUSolver())
    return _columns(sim.solve([0.0, end], t_interp=t_out, initial_soc=1.0))


def decimate(rows: np.ndarray, max_gap_s: float) -> np.ndarray:
    """Keep every sample next to a current change; others when V or T moved, or time passed."""
    t, i, v, temp = rows.T
    di = np.abs(np.diff(i)) > 1e-9 * max(float(np.max(np.abs(i))), 1e-12)
    edge = np.zeros(t.size, dtype=bool)
    edge[:-1] |= di
    edge[1:] |= di
    edge[0] = edge[-1] = True
    keep = np.zeros(t.size, dtype=bool)
    last = 0
    for k in range(t.size):
        if (edge[k] or t[k] - t[last] >= max_gap_s - 1e-9 or abs(v[k] - v[last]) >= DV_V
                or abs(temp[k] - temp[last]) >= DT_C):
            keep[k] = True
            last = k
    return rows[keep]


def write(rows: np.ndarray, path: str, what: str, max_gap_s: float = 120.0, every_sample: bool = False) -> None:
    kept = rows if every_sample else decimate(rows, max_gap_s)
    header = (f"# {what}\n# PyBaMM {pybamm.__version__} DFN, lumped thermal, parameter set {PARAMETER_SET}; "
              f"scripts/make_dfn_fixture.py ({rows.shape[0]} samples, {kept.shape[0]} kept)\n"
              "time_s,current_A,voltage_V,temp_C")
    np.savetxt(path, kept, delimiter=",", header=header, comments="", fmt=["%.3f", "%.6f", "%.5f", "%.3f"])
    print(f"{path}: {kept.shape[0]} of {rows.shape[0]} rows, {os.path.getsize(path) / 1024:.0f} kB")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("folder")
    ap.add_argument("--every-sample", action="store_true",
                    help="write every sample (no decimation): to check the decimated files' figures")
    args = ap.parse_args()
    os.makedirs(args.folder, exist_ok=True)
    out = lambda name: os.path.join(args.folder, name)  # noqa: E731
    full = {"every_sample": args.every_sample}
    _, p = model_and_parameters(25.0)
    cap = p["Nominal cell capacity [A.h]"]
    v_lo, v_hi = p["Lower voltage cut-off [V]"], p["Upper voltage cut-off [V]"]
    step = [f"Discharge at 1C for 10 seconds or until {v_lo} V", "Rest for 40 seconds",
            f"Charge at 0.75C for 10 seconds or until {v_hi} V", "Rest for 40 seconds",
            f"Discharge at C/2 for 12 minutes or until {v_lo} V", "Rest for 1 hour"]
    first = step[:2] + step[4:]   # a full cell takes no charge pulse
    last = step[:4] + [f"Discharge at C/2 until {v_lo} V", "Rest for 1 hour"]
    for temp in TEMPS_C:
        name = f"{temp:g}C"
        write(run_experiment(temp, ["Rest for 1 minute"] + first + step * 8 + last), out(f"hppc_{name}.csv"),
              f"HPPC at {temp:g} °C: per 10 % of SOC a 1C discharge and a 0.75C charge pulse, C/2 for 10 %, 1 h rest",
              **full)
        write(run_experiment(temp, ["Rest for 1 minute", f"Discharge at C/20 until {v_lo} V", "Rest for 1 hour"],
                             period="10 seconds"), out(f"c20_{name}.csv"),
              f"C/20 discharge at {temp:g} °C to {v_lo} V, then a 1 h rest", max_gap_s=600.0, **full)
        write(run_experiment(temp, ["Rest for 1 minute", f"Discharge at 1C until {v_lo} V", "Rest for 20 minutes"]),
              out(f"cc_1C_{name}.csv"), f"1C discharge at {temp:g} °C to {v_lo} V, then a 20 min rest", **full)
        write(run_profile(temp, drive_current(cap)), out(f"drive_{name}.csv"),
              f"drive cycle at {temp:g} °C: 12 min at 1C, then 3C peaks and regenerative braking to 2,400 s, a 600 s rest",
              max_gap_s=30.0, **full)


if __name__ == "__main__":
    main()
