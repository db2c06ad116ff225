#!/usr/bin/env python3
"""The 1-cell race side by side in one script: packsim's 10 ms runs against PyBaMM's
Thevenin model, interleaved round by round so every figure sees the same machine state
(a busy machine slows all of them alike). Run by bench/peers/.venv's Python (PyBaMM in
this process, built and discretised once up front); each packsim figure comes from a
child process of the system Python (as in run.sh) with PYTHONPATH set to a build's
python folder, so two packsim builds (before and after a change) can race in the same
rounds.

    bench/peers/.venv/bin/python bench/peers/one_cell.py \\
        [--packsim LABEL=PYTHONPATH ...] [--rounds 5] [--repeats 3] [--json OUT]

Default --packsim: now=build/python. Each round runs, for each build, `packsim_side.py
--time-cell SOLVER 10 REPEATS` (minimum CPU time of `packsim.run` over the repeats,
the fast and CVODE solvers) and each PyBaMM solver REPEATS times (CPU time of
`Simulation.solve`); a figure is the minimum over every round. Prints the table and
the ratios packsim / PyBaMM at its default settings; writes them as JSON with --json."""
from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time
import warnings

import common as c

warnings.filterwarnings("ignore")
os.environ.setdefault("TQDM_DISABLE", "1")
import peers_side  # noqa: E402  (PyBaMM, liionpack: this venv's)
import pybamm  # noqa: E402

PACKSIM_RUNS = (("fast", 10), ("cvode", 10))


def packsim_cpu_s(pythonpath: str, solver: str, tick_ms: int, repeats: int, python: str) -> dict:
    env = dict(os.environ, PYTHONPATH=pythonpath)
    r = subprocess.run([python, os.path.join(c.HERE, "packsim_side.py"), "--time-cell", solver, str(tick_ms),
                        str(repeats)], env=env, capture_output=True, text=True, cwd=c.HERE)
    if r.returncode != 0:
        raise SystemExit(f"one_cell: packsim ({pythonpath}) {solver} {tick_ms} ms failed:\n{r.stderr.strip()}")
    return json.loads(r.stdout.strip().splitlines()[-1])


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--packsim", action="append", default=[], metavar="LABEL=PYTHONPATH",
                    help="a packsim build's python folder (repeatable); default now=build/python")
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--python", default="python3", help="the Python that runs packsim (default: python3)")
    ap.add_argument("--json", help="write the figures here")
    a = ap.parse_args()
    builds = []
    for spec in a.packsim or [f"now={os.path.join(c.REPO, 'build', 'python')}"]:
        label, sep, path = spec.partition("=")
        if not sep or not label or not os.path.isdir(path):
            raise SystemExit(f"one_cell: --packsim {spec!r}: expected LABEL=PYTHONPATH with an existing folder")
        builds.append((label, os.path.abspath(path)))
    pybamm.set_logging_level("ERROR")
    sims = {name: peers_side.cell_simulation(name) for name in peers_side.CELL_SOLVERS}

    best: dict[str, float] = {}
    final_V: dict[str, float] = {}
    for rnd in range(a.rounds):
        for label, path in builds:
            for solver, tick in PACKSIM_RUNS:
                key = f"packsim[{label}] {solver} {tick} ms"
                r = packsim_cpu_s(path, solver, tick, a.repeats, a.python)
                best[key] = min(best.get(key, float("inf")), r["cpu_s"])
                final_V[key] = r["final_V"]
        for name, (sim, t_eval, _) in sims.items():
            key = f"pybamm {name} ({peers_side.solver_text(sim)})"
            for _ in range(a.repeats):
                t0 = time.process_time()
                sol = sim.solve(t_eval=t_eval, t_interp=t_eval)
                best[key] = min(best.get(key, float("inf")), time.process_time() - t0)
            final_V[key] = float(sol["Voltage [V]"].entries[-1])
        print(f"round {rnd + 1}/{a.rounds} done", file=sys.stderr, flush=True)

    race_h = c.LAPS * 100.0 / 3600.0
    default_key = next(k for k in best if k.startswith("pybamm default"))
    rows = {k: {"cpu_s": v, "cpu_s_per_cell_hour": v / race_h, "vs_pybamm_default": v / best[default_key],
                "final_V": final_V[k]} for k, v in best.items()}
    out = {"date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()), "rounds": a.rounds, "repeats": a.repeats,
           "pybamm": pybamm.__version__,
           "pybamm_default_solver": type(pybamm.equivalent_circuit.Thevenin().default_solver).__name__,
           "race_sim_s": c.LAPS * 100.0, "time": "CPU s, minimum over rounds x repeats", "rows": rows}
    print(f"1 cell, {c.LAPS * 100:.0f} s race, {a.rounds} rounds x {a.repeats} repeats (CPU s, minimum); "
          f"PyBaMM {pybamm.__version__}, its default solver for the Thevenin model: {out['pybamm_default_solver']}")
    print(f"  {'run':58s} {'s/race':>8s} {'s/cell-h':>9s} {'÷ PyBaMM default':>17s}")
    for k, r in rows.items():
        print(f"  {k:58s} {r['cpu_s']:8.4f} {r['cpu_s_per_cell_hour']:9.4f} {r['vs_pybamm_default']:17.2f}")
    if a.json:
        with open(a.json, "w") as f:
            json.dump(out, f, indent=2)


if __name__ == "__main__":
    main()
