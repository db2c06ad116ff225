#!/usr/bin/env python3
"""Result-file bytes and peak memory of representative runs, and what other HDF5
chunk/filter settings would make of the same files. Not a test: no threshold.

    PYTHONPATH=build/python python3 bench/output_memory.py [--packsim build/packsim] \\
        [--out /tmp/packsim-outmem] [--json bench/output_memory.json] [--quick]

Runs (each `packsim run` in its own process under /usr/bin/time: peak RSS, CPU time):
  system D, the bundled 20-minute race (110 cells, 1 Hz recording);
  system D scaled to 50s20p (1,000 cells) and 250s20p (5,000 cells) for one hour of
  racing (the lap current, shunt and over-current limits x20, as bench/bench_support.cpp's
  scaledPack does; the cell's capacity x3, 120 Ah, so one hour of racing does not empty
  it; ambient and start at 10 C, so it does not reach the 60 C over-temperature limit),
  fast integrator; 250s20p also for 10 minutes, to separate what grows
  with the run's length (the recording) from what does not.
For every file: its bytes (as packsim writes it: float channels to their stated
resolution with HDF5's scale-offset filter, docs/results.md), the datasets' bytes
uncompressed, and the datasets' stored bytes rewritten (h5py, in memory, from the values
as stored) with other settings: no filter; the lossless 16 Ki-value chunks with shuffle
and deflate 4 packsim wrote until 2026-11-24, and with deflate 1 / 9; chunks of 256 Ki values (deflate 4 + shuffle); deflate 4 without
shuffle; and, marked LOSSY, float32 or HDF5's scale-offset filter for the float data.
"""
from __future__ import annotations

import argparse
import csv
import json
import os
import platform
import subprocess
import tempfile
import time

import h5py

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCEN = os.path.join(REPO, "scenarios", "motorcycle_110s.yaml")
LAP = os.path.join(REPO, "scenarios", "profiles", "roadrace_lap.csv")
THERM_D = [2, 5, 8, 11, 14, 17, 20, 23, 26, 29, 32, 35, 38, 41, 44, 47, 50, 53, 56, 59, 62, 65, 68, 71, 74, 77, 80, 83,
           86, 89, 92, 95, 98, 101, 104, 107, 110]


def lap() -> tuple[list[float], list[float]]:
    with open(LAP, newline="") as f:
        rows = list(csv.DictReader(r for r in f if not r.lstrip().startswith("#")))
    return [float(r["time_s"]) for r in rows], [float(r["current_A"]) for r in rows]


def scaled(series: int, parallel: int, duration_s: float) -> list[str]:
    """--set overrides making system D series x parallel at the same C-rate (scaledPack)."""
    t, i = lap()
    p = float(parallel)
    therm = [c for c in THERM_D if c <= series]
    sets = {
        "pack.series": series, "pack.parallel": parallel, "pack.interconnect_ohm": 1e-4 * series / p,
        "hardware.thermistors.at_groups": json.dumps(therm),
        "hardware.current_sense.shunt_ohm": 1e-4 / p,
        "bms.protections.overcurrent_discharge": f"{{threshold_A: {400 * p}, hysteresis_A: {10 * p}, delay_ms: 500}}",
        "bms.protections.overcurrent_charge": f"{{threshold_A: {120 * p}, hysteresis_A: {5 * p}, delay_ms: 500}}",
        "load": json.dumps({"points": {"time_s": t, "current_A": [x * p for x in i]}, "interpolation": "linear",
                            "laps": 1000}),
        "run.duration_s": duration_s, "run.solver": "fast",
        # An hour of racing empties a 40 Ah cell (the bundled race takes 30 Ah in 20 min):
        # 3x the capacity lasts the hour, with the same data recorded.
        "pack.cell.capacity_Ah": 120,
        # ... and reaches the 60 C over-temperature limit from 30 C after ~54 min: start at 10 C.
        "ambient.temp_C": 10, "pack.initial_temp_C": 10,
    }
    out = []
    for k, v in sets.items():
        out += ["--set", f"{k}={v}"]
    return out


def run(packsim: str, args: list[str], h5: str) -> dict:
    cmd = ["/usr/bin/time", "-f", "%M %U %S %e", packsim, "run", SCEN, *args, "-o", h5, "-q"]
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode != 0:
        raise SystemExit(f"packsim failed ({p.returncode}): {p.stderr[-2000:]}")
    rss_kB, user, sys_, wall = p.stderr.strip().splitlines()[-1].split()
    return {"peak_rss_MB": int(rss_kB) / 1e3, "cpu_s": float(user) + float(sys_), "wall_s": float(wall)}


def variants(h5: str) -> dict:
    """Stored bytes of the datasets under other chunk/filter settings (same values)."""
    def chunks_16k(shape):
        if len(shape) == 0 or shape[0] == 0:
            return None
        cols = shape[1] if len(shape) == 2 else 1
        rows = min(shape[0], max(1, 16384 // max(1, cols)))
        return (rows,) + tuple(shape[1:])

    def chunks_big(shape):
        if len(shape) == 0 or shape[0] == 0:
            return None
        cols = shape[1] if len(shape) == 2 else 1
        rows = min(shape[0], max(1, 262144 // max(1, cols)))
        return (rows,) + tuple(shape[1:])

    settings = {
        "none (contiguous)": dict(chunks=lambda s: None, compression=None, shuffle=False),
        "lossless as until 2026-11-24: 16 Ki-value chunks, shuffle + deflate 4": dict(chunks=chunks_16k, compression=4, shuffle=True),
        "16 Ki-value chunks, shuffle + deflate 1": dict(chunks=chunks_16k, compression=1, shuffle=True),
        "16 Ki-value chunks, shuffle + deflate 9": dict(chunks=chunks_16k, compression=9, shuffle=True),
        "16 Ki-value chunks, deflate 4 (no shuffle)": dict(chunks=chunks_16k, compression=4, shuffle=False),
        "256 Ki-value chunks, shuffle + deflate 4": dict(chunks=chunks_big, compression=4, shuffle=True),
        # Lossy, for scale: what changing the stored values (not the filters) would give.
        "LOSSY float64 -> float32, 16 Ki-value chunks, shuffle + deflate 4": dict(chunks=chunks_16k, compression=4, shuffle=True,
                                                                     float32=True),
        "LOSSY scale-offset 1e-6 (floats), shuffle + deflate 4": dict(chunks=chunks_16k, compression=4, shuffle=True,
                                                                      scaleoffset=6),
    }
    out = {}
    with h5py.File(h5, "r") as src:
        items = []
        src.visititems(lambda n, o: items.append((n, o)) if isinstance(o, h5py.Dataset) else None)
        raw = sum(o.size * o.dtype.itemsize for _, o in items)
        stored = sum(o.id.get_storage_size() for _, o in items)
        for name, s in settings.items():
            total = 0
            with h5py.File(f"in-memory {name}", "w", driver="core", backing_store=False) as dst:
                for n, o in items:
                    data = o[()]
                    floats = o.dtype.kind == "f" and o.dtype.fields is None
                    if s.get("float32") and floats:
                        data = data.astype("float32")
                    ch = s["chunks"](o.shape)
                    kw = {}
                    if ch is not None and o.size > 0 and s["compression"] is not None:
                        kw = {"chunks": ch, "compression": "gzip", "compression_opts": s["compression"],
                              "shuffle": s["shuffle"]}
                        if s.get("scaleoffset") and floats:
                            kw["scaleoffset"] = s["scaleoffset"]
                    d = dst.create_dataset(n, data=data, **kw)
                    total += d.id.get_storage_size()
            out[name] = total
    return {"raw_dataset_bytes": raw, "stored_dataset_bytes": stored, "stored_bytes_by_setting": out}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--packsim", default=os.path.join(REPO, "build", "packsim"))
    ap.add_argument("--out", default=os.path.join(tempfile.gettempdir(), "packsim-outmem"))
    ap.add_argument("--json")
    ap.add_argument("--quick", action="store_true", help="10-minute runs instead of an hour (a smoke run)")
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    hour = 600.0 if a.quick else 3600.0
    runs = [
        ("system D race (110s1p, 20 min)", 110, 1200.0, []),
        (f"50s20p, {hour / 60:.0f} min", 1000, hour, scaled(50, 20, hour)),
        ("250s20p, 10 min", 5000, 600.0, scaled(250, 20, 600.0)),
        (f"250s20p, {hour / 60:.0f} min", 5000, hour, scaled(250, 20, hour)),
    ]
    res = {"date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()),
           "machine": f"{platform.machine()}, {os.cpu_count()} cores", "runs": {}}
    for label, cells, sim_s, args in runs:
        h5 = os.path.join(a.out, f"{cells}_{int(sim_s)}.h5")
        m = run(a.packsim, args, h5)
        with h5py.File(h5, "r") as f:
            tripped = int(f["summary"].attrs.get("tripped", 0))
            ran_s = float(f["time_s"][-1])
        if tripped or ran_s < sim_s - 1:
            raise SystemExit(f"{h5}: the run ended at {ran_s} s (tripped: {tripped}); the figures need the whole run")
        m.update({"cells": cells, "sim_s": sim_s, "file_bytes": os.path.getsize(h5),
                  "peak_rss_MB_per_1000_cells": m["peak_rss_MB"] / cells * 1000})
        m.update(variants(h5))
        res["runs"][label] = m
        print(json.dumps({label: m}, indent=1), flush=True)
    if a.json:
        with open(a.json, "w") as f:
            json.dump(res, f, indent=2)


if __name__ == "__main__":
    main()
