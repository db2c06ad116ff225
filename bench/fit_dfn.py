"""`packsim fit` on cell-test data from PyBaMM's DFN model (the fixture of
tests/data/dfn_ecker2015, made by scripts/make_dfn_fixture.py): training and held-out
errors per file, and the fit times. Not a test: no thresholds (tests/python/test_fit_dfn.py
guards the joint fit's figures).

    PYTHONPATH=build/python python3 bench/fit_dfn.py [FOLDER] [--json out.json] [--check FULL_FOLDER]

Two fits, 2 RC pairs, smoothing 0.1, capacity measured (the C/20 discharges):
  25 °C      trained on hppc_25C and c20_25C (no temperature law)
  joint      HPPC and C/20 at 0, 25 and 40 °C: Arrhenius laws and the OCV's temperature
             coefficient, every sample at its measured temperature
Held out from both: 1C discharges and drive cycles at 0, 25 and 40 °C. Per file: RMS over
time, maximum and RMS over time below 10 % SOC of the voltage error (model − DFN), in mV.
The fixture is decimated (samples kept where the voltage moves), so every sample is
weighted by the time it stands for (FileFit.rms_over_time_mV). --check FULL_FOLDER also
runs the written presets over the undecimated records (make_dfn_fixture.py --every-sample)
to show the weighting gives their figures.
"""
from __future__ import annotations

import argparse
import json
import os
import time
import warnings

FIXTURE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "data", "dfn_ecker2015")
TEMPS = (0, 25, 40)
TRAIN = {"25 °C": ["hppc_25C.csv", "c20_25C.csv"],
         "joint": [f"{kind}_{t}C.csv" for kind in ("hppc", "c20") for t in TEMPS]}
HELD_OUT = [f"{kind}_{t}C.csv" for kind in ("cc_1C", "drive") for t in TEMPS]
LOW_SOC = 0.1


def errors(f) -> dict:
    return {"samples": f.samples, "rms_mV": f.rms_over_time_mV(), "max_mV": f.max_mV,
            "low_soc_rms_mV": f.rms_over_time_mV(LOW_SOC)}


def run(folder: str, train: list[str], check: str | None) -> dict:
    import packsim
    paths = [os.path.join(folder, n) for n in train]
    held = [os.path.join(folder, n) for n in HELD_OUT]
    c, w = time.process_time(), time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        packsim.fit(paths, rc_pairs=2, smoothing=0.1, max_evaluations=2000)   # the time without held-out files
        cpu, wall = time.process_time() - c, time.perf_counter() - w
        f = packsim.fit(paths, rc_pairs=2, validate=held, smoothing=0.1, max_evaluations=2000)
    rows = {os.path.basename(x.name): {"held_out": h, **errors(x)}
            for h, group in ((False, f.files), (True, f.validation)) for x in group}
    out = {"cpu_s": cpu, "wall_s": wall, "evaluations": f.evaluations, "capacity_Ah": f.capacity_Ah,
           "rows": sum(x.samples for x in f.files), "summary": f.summary(), "files": rows}
    if check:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            full = packsim.fit(paths, rc_pairs=2, smoothing=0.1, max_evaluations=2000,
                               validate=[os.path.join(check, n) for n in train + HELD_OUT])
        out["undecimated"] = {os.path.basename(x.name): errors(x) for x in full.validation}
    return out


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("folder", nargs="?", default=FIXTURE)
    p.add_argument("--json")
    p.add_argument("--check", metavar="FULL_FOLDER")
    args = p.parse_args()
    fits = {k: run(args.folder, train, args.check) for k, train in TRAIN.items()}
    names = TRAIN["joint"] + HELD_OUT
    fmt = lambda v: "—" if v is None else f"{v:.1f}"  # noqa: E731
    cell = lambda r: "—" if r is None else f"{fmt(r['rms_mV'])} / {fmt(r['max_mV'])} / {fmt(r['low_soc_rms_mV'])}"  # noqa: E731
    print(f"{'file':<16}{'':>9}" + "".join(f"{k + ': RMS / max / <10 % SOC':>34}" for k in fits))
    for n in names:
        role = "held out" if n in HELD_OUT else "train"
        print(f"{n:<16}{role:>9}" + "".join(f"{cell(fit['files'].get(n)):>34}" for fit in fits.values()))
    for k, fit in fits.items():
        print(f"{k}: {fit['cpu_s']:.2f} s CPU, {fit['wall_s']:.2f} s wall, {fit['rows']} rows, "
              f"{fit['evaluations']} evaluations, capacity {fit['capacity_Ah']:.4g} Ah")
        if "undecimated" in fit:
            print(f"  {k}, the same preset over the undecimated records:")
            for n, r in fit["undecimated"].items():
                print(f"    {n:<16}{r['samples']:>7} samples  {cell(r)}")
    if args.json:
        with open(args.json, "w") as out:
            json.dump(fits, out, indent=1)


if __name__ == "__main__":
    main()
