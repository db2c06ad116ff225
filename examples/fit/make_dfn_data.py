"""Cell-test data from a physics model nobody here wrote: PyBaMM's DFN (Doyle-Fuller-Newman)
with a lumped thermal model and the published Ecker2015 parameter set (a Kokam NMC/graphite
pouch cell, with Arrhenius kinetics and diffusion), as a lab would record it.

    python3 -m venv .venv-dfn && .venv-dfn/bin/pip install pybamm==25.4.2
    .venv-dfn/bin/python examples/fit/make_dfn_data.py dfn-data/

Each test starts with the cell full and rested at its chamber temperature; columns
time_s,current_A,voltage_V,temp_C (positive current discharges), no added noise:

  training  hppc_25C     per 10 % of SOC a 10 s 1C discharge pulse, a 10 s 0.75C charge pulse,
                         10 % of capacity at C/2 and a 1 h rest, one row a second
            c20_25C      C/20 to the cut-off, a row every 10 s
            cc_C2_0C     C/2 to the cut-off at 0 °C and 40 °C, no rest at all: the files
            cc_C2_40C    `packsim fit` used to refuse, now used for the temperature law
  held out  cc_1C_{0,25,40}C     1C to the cut-off
            drive_{0,25,40}C     12 minutes at 1C, then a drive cycle (0.8C mean, 3C peaks,
                                 regenerative braking) to 2,400 s, then a 600 s rest; a row a second

Used by bench/fit_dfn.py, whose figures are in docs/fit.md. Takes a few minutes.
"""
from __future__ import annotations

import argparse
import os

import numpy as np
import pybamm

TEMPS_C = (0.0, 25.0, 40.0)


def model_and_parameters(temp_C: float):
    model = pybamm.lithium_ion.DFN(options={"thermal": "lumped"})
    p = pybamm.ParameterValues("Ecker2015")
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


def run(temp_C: float, experiment=None, current=None, period_s: float = 1.0):
    model, p = model_and_parameters(temp_C)
    solver = pybamm.IDAKLUSolver()
    if current is not None:
        # a current profile held piecewise constant; PyBaMM's current is positive on discharge
        starts, values = current[:-1, 0], current[:-1, 1]
        ends = current[1:, 0]
        t_knots = np.column_stack([starts, ends - 1e-3]).ravel()  # steps, not ramps
        i_knots = np.repeat(values, 2)
        p["Current function [A]"] = pybamm.Interpolant(t_knots, i_knots, pybamm.t, interpolator="linear")
        t_knots = current[:, 0]
        t_out = np.arange(0.0, t_knots[-1] + period_s / 2, period_s)
        sim = pybamm.Simulation(model, parameter_values=p, solver=solver)
        sol = sim.solve([0.0, t_knots[-1]], t_interp=t_out, initial_soc=1.0)
    else:
        sim = pybamm.Simulation(model, parameter_values=p, experiment=experiment, solver=solver)
        sol = sim.solve(initial_soc=1.0)
    t = sol["Time [s]"].entries
    i = sol["Current [A]"].entries
    v = sol["Voltage [V]"].entries
    temp = sol["X-averaged cell temperature [K]"].entries - 273.15
    keep = np.concatenate(([True], np.diff(t) > 1e-6))  # experiment steps repeat their boundary
    return np.column_stack([t, i, v, temp])[keep]


def write(rows: np.ndarray, path: str) -> str:
    np.savetxt(path, rows, delimiter=",", header="time_s,current_A,voltage_V,temp_C", comments="",
               fmt=["%.3f", "%.6f", "%.6f", "%.3f"])
    print(path, rows.shape[0], "rows")
    return path


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("folder")
    args = ap.parse_args()
    os.makedirs(args.folder, exist_ok=True)
    out = lambda name: os.path.join(args.folder, name)  # noqa: E731
    _, p = model_and_parameters(25.0)
    cap = p["Nominal cell capacity [A.h]"]
    cut = p["Lower voltage cut-off [V]"]
    hppc = pybamm.Experiment([("Discharge at 1C for 10 seconds", "Rest for 40 seconds",
                               "Charge at 0.75C for 10 seconds", "Rest for 40 seconds",
                               f"Discharge at C/2 for 12 minutes or until {cut} V", "Rest for 1 hour")] * 9,
                             period="1 second")
    write(run(25.0, hppc), out("hppc_25C.csv"))
    write(run(25.0, pybamm.Experiment([f"Discharge at C/20 until {cut} V"], period="10 seconds")), out("c20_25C.csv"))
    for t in (0.0, 40.0):
        write(run(t, pybamm.Experiment([f"Discharge at C/2 until {cut} V"], period="1 second")), out(f"cc_C2_{t:g}C.csv"))
    for t in TEMPS_C:
        write(run(t, pybamm.Experiment([f"Discharge at 1C until {cut} V"], period="1 second")), out(f"cc_1C_{t:g}C.csv"))
        write(run(t, current=drive_current(cap)), out(f"drive_{t:g}C.csv"))


if __name__ == "__main__":
    main()
