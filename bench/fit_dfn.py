"""`packsim fit` on cell-test data from PyBaMM's DFN model (examples/fit/make_dfn_data.py):
training and held-out errors per file, and the fit times. Not a test: no thresholds.

    .venv-dfn/bin/python examples/fit/make_dfn_data.py dfn-data/        # once, a minute or two
    PYTHONPATH=build/python python3 bench/fit_dfn.py dfn-data/ [--json out.json]

Two fits, 2 RC pairs, the default smoothing, capacity measured (the C/20 discharge):
  25 °C      trained on hppc_25C and c20_25C (no temperature law)
  joint      the same plus the rest-free C/2 discharges at 0 and 40 °C: Arrhenius laws,
             every sample at its measured temperature
Held out from both: 1C discharges and drive cycles at 0, 25 and 40 °C. Per file: RMS,
maximum and RMS below 10 % SOC of the voltage error (model − DFN), in mV.
"""
from __future__ import annotations

import argparse
import json
import os
import time
import warnings

TRAIN_25 = ["hppc_25C.csv", "c20_25C.csv"]
TRAIN_T = ["cc_C2_0C.csv", "cc_C2_40C.csv"]
HELD_OUT = [f"{kind}_{t}C.csv" for kind in ("cc_1C", "drive") for t in (0, 25, 40)]


def run(folder: str, train: list[str]) -> dict:
    import packsim
    c, w = time.process_time(), time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        f = packsim.fit([os.path.join(folder, n) for n in train], rc_pairs=2,
                        validate=[os.path.join(folder, n) for n in HELD_OUT], smoothing=0.1, max_evaluations=2000)
    cpu, wall = time.process_time() - c, time.perf_counter() - w
    rows = {os.path.basename(x.name): {"held_out": held, "samples": x.samples, "rms_mV": x.rms_mV,
                                        "max_mV": x.max_mV, "low_soc_rms_mV": x.low_soc_rms_mV}
            for held, group in ((False, f.files), (True, f.validation)) for x in group}
    return {"cpu_s": cpu, "wall_s": wall, "evaluations": f.evaluations, "capacity_Ah": f.capacity_Ah,
            "summary": f.summary(), "files": rows}


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("folder")
    p.add_argument("--json")
    args = p.parse_args()
    fits = {"25 °C": run(args.folder, TRAIN_25), "joint": run(args.folder, TRAIN_25 + TRAIN_T)}
    names = TRAIN_25 + TRAIN_T + HELD_OUT
    low = lambda v: "—" if v is None else f"{v:.1f}"  # noqa: E731
    print(f"{'file':<18}{'':>9}" + "".join(f"{k + ': RMS / max / <10 % SOC':>34}" for k in fits))
    for n in names:
        cells = []
        for fit in fits.values():
            r = fit["files"].get(n)
            cells.append("—" if r is None else f"{r['rms_mV']:.1f} / {r['max_mV']:.1f} / {low(r['low_soc_rms_mV'])}")
        role = "held out" if n in HELD_OUT else "train"
        print(f"{n:<18}{role:>9}" + "".join(f"{c:>34}" for c in cells))
    for k, fit in fits.items():
        print(f"{k}: {fit['cpu_s']:.2f} s CPU, {fit['wall_s']:.2f} s wall, {fit['evaluations']} evaluations, "
              f"capacity {fit['capacity_Ah']:.4g} Ah")
    if args.json:
        with open(args.json, "w") as out:
            json.dump(fits, out, indent=1)


if __name__ == "__main__":
    main()
