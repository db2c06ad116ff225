#!/usr/bin/env python3
"""The peers' side of the comparison (run by bench/peers/.venv's Python, pinned in
requirements.txt): PyBaMM's Thevenin model on the 1-cell race, and liionpack on the
16s4p race with the same Thevenin cell. CPU time of the solve (the model built and
discretised once beforehand, as a user running many races would), minimum of the
repeats, and the voltages. Writes one .npz (argv[1])."""
from __future__ import annotations

import json
import sys
import time
import warnings

import numpy as np
import pybamm
import liionpack as lp

import common as c

warnings.filterwarnings("ignore")
pybamm.set_logging_level("ERROR")


def parameter_values() -> pybamm.ParameterValues:
    """PyBaMM's ECM example set with the cell of common.py in place of its own."""
    pv = pybamm.ParameterValues("ECM_Example")

    def ocv(soc):
        return pybamm.Interpolant(np.array(c.OCV_SOC), np.array(c.OCV_V), soc, interpolator="linear")

    def r0(T_cell, current, soc):
        return pybamm.Interpolant(np.array(c.R0_SOC), np.array(c.R0_OHM), soc, interpolator="linear")

    def r1(T_cell, current, soc):
        return pybamm.Scalar(c.R1_OHM)

    def c1(T_cell, current, soc):
        return pybamm.Scalar(c.TAU1_S / c.R1_OHM)

    def entropic(T_cell, soc):
        return pybamm.Scalar(0.0)

    pv.update({
        "Cell capacity [A.h]": c.CAPACITY_AH, "Nominal cell capacity [A.h]": c.CAPACITY_AH,
        "Open-circuit voltage [V]": ocv, "R0 [Ohm]": r0, "R1 [Ohm]": r1, "C1 [F]": c1,
        "Entropic change [V/K]": entropic, "Initial SoC": c.INITIAL_SOC,
        "Ambient temperature [K]": 273.15 + c.AMBIENT_C, "Initial temperature [K]": 273.15 + c.AMBIENT_C,
        "Lower voltage cut-off [V]": 2.5, "Upper voltage cut-off [V]": 4.5,
    })
    return pv


# PyBaMM's Thevenin model on each solver: its default (PyBaMM 25.4.2: IDAKLUSolver with
# its default tolerances, rtol 1e-4, atol 1e-6, what `pybamm.Simulation(model)` picks),
# IDAKLU at tight tolerances, and CasADi's fast mode at the same.
CELL_SOLVERS = ("default", "idaklu", "casadi")


def cell_solver(name: str):
    if name == "default":
        return None  # pybamm.Simulation picks the model's default_solver
    if name == "idaklu":
        return pybamm.IDAKLUSolver(rtol=1e-6, atol=1e-8)
    return pybamm.CasadiSolver(mode="fast", rtol=1e-6, atol=1e-8)


def cell_simulation(name: str):
    """(simulation built and discretised, t_eval, build CPU s) of the 1-cell race."""
    t, i = c.race_profile()
    pv = parameter_values()
    pv["Current function [A]"] = pybamm.Interpolant(np.array(t), np.array(i), pybamm.t, interpolator="linear")
    model = pybamm.equivalent_circuit.Thevenin()
    t_eval = np.arange(0.0, t[-1] + 0.5, 1.0)
    solver = cell_solver(name)
    t0 = time.process_time()
    sim = (pybamm.Simulation(model, parameter_values=pv, solver=solver) if solver is not None
           else pybamm.Simulation(model, parameter_values=pv))
    sim.build()
    return sim, t_eval, time.process_time() - t0


def solver_text(sim) -> str:
    s = sim.solver
    return f"{type(s).__name__}, rtol {s.rtol:g}, atol {s.atol:g}"


def pybamm_cell(repeats: int) -> dict:
    out = {}
    for name in CELL_SOLVERS:
        sim, t_eval, build_s = cell_simulation(name)
        best, sol = float("inf"), None
        for _ in range(repeats):
            t0 = time.process_time()
            sol = sim.solve(t_eval=t_eval, t_interp=t_eval)
            best = min(best, time.process_time() - t0)
        out[name] = {"cpu_s": best, "build_cpu_s": build_s, "t": sol["Time [s]"].entries,
                     "V": sol["Voltage [V]"].entries, "soc_end": float(sol["SoC"].entries[-1]),
                     "solver": solver_text(sim)}
        print(f"pybamm thevenin ({name}: {solver_text(sim)}): solve {best:.3f} s CPU, build {build_s:.3f} s", flush=True)
    return out


def liionpack_pack(repeats: int) -> dict:
    pv = parameter_values()
    amps = [a * c.PACK_PARALLEL for a in c.race_per_second()]
    experiment = pybamm.Experiment([pybamm.step.current(np.column_stack([np.arange(len(amps), dtype=float),
                                                                          np.array(amps)]))],
                                  period="1 second")

    def sim_func(parameter_values):
        model = pybamm.equivalent_circuit.Thevenin()
        # liionpack reads these two names from every cell model.
        model.variables["Terminal voltage [V]"] = model.variables["Voltage [V]"]
        model.variables["Surface open-circuit voltage [V]"] = model.variables["Open-circuit voltage [V]"]
        model = lp.add_events_to_model(model)
        return pybamm.Simulation(model, parameter_values=parameter_values.copy(),
                                 solver=pybamm.CasadiSolver(mode="safe"))

    # Busbars and connections negligible (packsim's equivalent pack has none).
    netlist = lp.setup_circuit(Np=c.PACK_PARALLEL, Ns=c.PACK_SERIES, Rb=1e-7, Rc=1e-7, Rt=1e-7, Ri=1e-3, V=3.9)
    best, out = float("inf"), None
    for _ in range(repeats):
        t0 = time.process_time()
        out = lp.solve(netlist=netlist, sim_func=sim_func, parameter_values=pv, experiment=experiment,
                       initial_soc=None, nproc=1, manager="casadi")
        best = min(best, time.process_time() - t0)
    print(f"liionpack 16s4p (Thevenin cells, casadi manager): {best:.3f} s CPU", flush=True)
    return {"cpu_s": best, "pack_V": np.asarray(out["Pack terminal voltage [V]"], dtype=float),
            "cell_V": np.asarray(out["Terminal voltage [V]"], dtype=float),
            "cell_I": np.asarray(out["Cell current [A]"], dtype=float)}


def main() -> None:
    dest, repeats = sys.argv[1], int(sys.argv[2]) if len(sys.argv) > 2 else 3
    cell = pybamm_cell(repeats)
    pack = liionpack_pack(1)  # minutes per run: once
    arrays = {}
    meta = {"pybamm_version": pybamm.__version__, "liionpack_version": lp.__version__, "solvers": {}}
    for name, r in cell.items():
        arrays[f"pybamm_{name}_t"], arrays[f"pybamm_{name}_V"] = r["t"], r["V"]
        meta["solvers"][f"pybamm_{name}"] = {"cpu_s": r["cpu_s"], "build_cpu_s": r["build_cpu_s"], "soc_end": r["soc_end"],
                                             "solver": r["solver"]}
    arrays["liionpack_pack_V"], arrays["liionpack_cell_V"] = pack["pack_V"], pack["cell_V"]
    arrays["liionpack_cell_I"] = pack["cell_I"]
    meta["solvers"]["liionpack"] = {"cpu_s": pack["cpu_s"], "cell_model": "pybamm.equivalent_circuit.Thevenin",
                                    "manager": "casadi", "nproc": 1}
    np.savez(dest, meta=json.dumps(meta), **arrays)


if __name__ == "__main__":
    main()
