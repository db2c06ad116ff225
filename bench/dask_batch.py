#!/usr/bin/env python3
"""Monte Carlo races of system D on a local Dask cluster: wall time, and the memory of
the client and of every worker sampled through the run (bounded memory = the same
resident size after 10 % of the cases as after all of them).

    PYTHONPATH=build/python python3 bench/dask_batch.py --cases 1000 --out /tmp/mc1000 \\
        [--workers 2] [--json bench/dask_batch.json]

Each case is the bundled system D race (scenarios/motorcycle_110s.yaml, 20 minutes, fast
integrator; --duration-s shortens it) with its own cell-spread seed. Rerunning with the same --out resumes: the
figures then count only the cases still to run. Not a test: no threshold.
"""
from __future__ import annotations

import argparse
import json
import os
import platform
import resource
import subprocess
import threading
import time

import psutil
from distributed import Client, LocalCluster

import packsim


def rss_tree_MB(pid: int) -> dict[int, float]:
    """Resident size of a process and of each of its descendants, in MB."""
    out = {}
    try:
        root = psutil.Process(pid)
        for p in [root, *root.children(recursive=True)]:
            try:
                out[p.pid] = p.memory_info().rss / 1e6
            except psutil.Error:
                pass
    except psutil.Error:
        pass
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--cases", type=int, default=1000)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--duration-s", type=float, default=None,
                    help="race length (run.duration_s); default: the bundled 20-minute race")
    ap.add_argument("--out", required=True, help="output folder of the sweep (result files, summary.csv)")
    ap.add_argument("--json", help="write the figures here as JSON too")
    a = ap.parse_args()
    if a.cases < 1 or a.workers < 1:
        ap.error("--cases and --workers must be >= 1")
    if a.duration_s is not None and not a.duration_s > 0:
        ap.error("--duration-s must be > 0")

    base = packsim.bundled_scenarios("motorcycle_110s.yaml")[0]
    sweep = {"name": f"mc{a.cases}", "base": base, "grid": {"run.solver": ["fast"]},
             "monte_carlo": {"samples": a.cases, "master_seed": 2026}}
    if a.duration_s is not None:
        sweep["grid"]["run.duration_s"] = [a.duration_s]

    samples: list[tuple[float, int, float, float]] = []  # (t s, cases done, client MB, max worker MB)
    stop = threading.Event()
    journal = os.path.join(a.out, "summary.running.jsonl")

    def sample(t0: float, workers: list[int]) -> None:
        me = os.getpid()
        while not stop.is_set():
            rss = rss_tree_MB(me)
            done = samples[-1][1] if samples else 0  # the journal is removed when the sweep ends
            if os.path.exists(journal):
                with open(journal, "rb") as f:
                    done = max(done, sum(1 for _ in f))
            samples.append((time.perf_counter() - t0, done, rss.get(me, 0.0),
                            max((v for k, v in rss.items() if k in workers), default=0.0)))
            stop.wait(1.0)

    with LocalCluster(n_workers=a.workers, threads_per_worker=1, processes=True, dashboard_address=":0",
                      silence_logs=40) as cluster, Client(cluster) as client:
        workers = [int(v) for v in client.run(os.getpid).values()]
        t0 = time.perf_counter()
        sampler = threading.Thread(target=sample, args=(t0, workers), daemon=True)
        sampler.start()
        res = packsim.batch(sweep, client, output_dir=a.out)
        wall_s = time.perf_counter() - t0
        stop.set()
        sampler.join()
        worker_peak_MB = {str(k): v.get("ru_maxrss_MB") for k, v in client.run(
            lambda: {"ru_maxrss_MB": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1e3}).items()}
        worker_cpu_s = sum(client.run(lambda: sum(resource.getrusage(resource.RUSAGE_SELF)[:2])).values())

    def at_fraction(frac: float) -> dict:
        want = frac * a.cases
        row = next((s for s in samples if s[1] >= want), samples[-1] if samples else (0, 0, 0, 0))
        return {"t_s": round(row[0], 1), "cases_done": row[1], "client_MB": round(row[2], 1),
                "worker_max_MB": round(row[3], 1)}

    out_bytes = sum(os.path.getsize(p) for p in res.paths if p)
    figures = {
        "date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()),
        "machine": f"{platform.processor() or platform.machine()}, {os.cpu_count()} cores",
        "commit": subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True,
                                 cwd=os.path.dirname(os.path.abspath(__file__))).stdout.strip(),
        "cases": len(res), "ok": res.n_ok, "failed": res.n_failed, "skipped": res.n_skipped,
        "race_s": a.duration_s or 1200.0, "workers": a.workers, "wall_s": round(wall_s, 1), "worker_cpu_s": round(worker_cpu_s, 1),
        "s_per_case_wall": round(wall_s / max(1, len(res) - res.n_skipped), 3),
        "client_peak_rss_MB": round(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1e3, 1),
        "worker_peak_rss_MB": worker_peak_MB,
        "rss_at": {f"{int(f * 100)}%": at_fraction(f) for f in (0.1, 0.25, 0.5, 0.75, 1.0)},
        "result_bytes_total": out_bytes,
    }
    print(json.dumps(figures, indent=2))
    if a.json:
        with open(a.json, "w") as f:
            json.dump(figures, f, indent=2)


if __name__ == "__main__":
    main()
