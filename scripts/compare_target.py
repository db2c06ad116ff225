#!/usr/bin/env python3
"""Host mode against target mode for packsim's core: runs each scenario twice with the
same binary and seed -- packsim's core linked in (host mode) and as ARM code on the
virtual Cortex-M4 (`packsim run --target cortex-m4`) -- and compares the decisions.

    scripts/compare_target.py [--packsim build/packsim] [--jobs 2] [--timeout S] [--out TABLE.tsv] [SCENARIO...]

Without scenarios: every bundled one (scenarios/**/*.yaml as `packsim check` collects
them). A scenario that runs a firmware library in host mode, or a pack of several
monitor boards, is reported as `skipped` with packsim's reason.

Decisions are the run's events other than `relay_contact` (its instant follows the
code's cycles, microseconds) and `firmware_loaded`: each kind, detail and time; the
trip (time, reason) from the summary. One TSV row per scenario: host and target trip,
whether every decision matched (else the first that differs), the worst cycles of
each task, the CPU load, the latest relay contact shift, and each run's CPU seconds.
Exit status 1 when any decision differs.
"""
import argparse
import concurrent.futures as cf
import os
import re
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import h5py

ROOT = Path(__file__).resolve().parent.parent


def collect(paths):
    out = []
    for p in paths:
        p = Path(p)
        if p.is_file():
            out.append(p)
            continue
        for f in sorted(p.rglob("*.yaml")):
            if not ({"cells", "profiles"} & set(f.relative_to(p).parts[:-1])):
                out.append(f)
    return out


def run(packsim, scenario, target, h5, timeout):
    args = [packsim, "run", str(scenario), "-o", h5]
    if target:
        args += ["--target", "cortex-m4"]
    # This child's own CPU time (os.wait4), not RUSAGE_CHILDREN, which --jobs > 1 shares.
    with tempfile.TemporaryFile("w+") as out, tempfile.TemporaryFile("w+") as err:
        p = subprocess.Popen(args, stdout=out, stderr=err, text=True)
        try:
            _, status, usage = wait4(p.pid, timeout)
        except subprocess.TimeoutExpired:
            p.kill()
            p.wait()
            raise
        out.seek(0)
        err.seek(0)
        done = subprocess.CompletedProcess(args, os.waitstatus_to_exitcode(status), out.read(), err.read())
    return done, usage.ru_utime + usage.ru_stime


def wait4(pid, timeout):
    """os.wait4 with a wall-time limit (None: none)."""
    start = time.monotonic()
    while True:
        got, status, usage = os.wait4(pid, os.WNOHANG if timeout else 0)
        if got == pid:
            return got, status, usage
        if time.monotonic() - start > timeout:
            raise subprocess.TimeoutExpired(str(pid), timeout)
        time.sleep(0.2)


def events(h5):
    with h5py.File(h5) as f:
        ev = f["events"][:]
    dec, contact = [], []
    for t, k, d in ev:
        k, d = k.decode(), d.decode()
        if k == "firmware_loaded":
            continue
        if k == "relay_contact":
            contact.append((t, d))
        else:
            dec.append((round(t, 6), k, d))
    return dec, contact


def trip(stdout):
    m = re.search(r"^BMS\s+TRIP at ([0-9.]+) s\s+\(([^)]*)\)", stdout, re.M)
    return f"{m.group(1)} s {m.group(2)}" if m else "no trip"


def target_figures(stdout):
    worst = re.findall(r"^target\s+task (\d+) \(period (\d+) ms\).*?worst \d+ instructions / (\d+) cycles", stdout, re.M)
    load = re.search(r"CPU load ([0-9.]+) %", stdout)
    stack = re.search(r"stack high-water (\d+) of", stdout)
    return (" / ".join(f"t{t}: {c}" for t, _, c in worst), load.group(1) if load else "-",
            stack.group(1) if stack else "-")


def compare(packsim, scenario, tmp, timeout):
    name = str(scenario.relative_to(ROOT / "scenarios")) if ROOT / "scenarios" in scenario.parents else str(scenario)
    tag = re.sub(r"\W", "_", name)
    hh, th = os.path.join(tmp, tag + "_host.h5"), os.path.join(tmp, tag + "_target.h5")
    try:
        t, tcpu = run(packsim, scenario, True, th, timeout)
    except subprocess.TimeoutExpired:
        return [name, "not compared", f"the target run took over {timeout} s of wall time (--timeout)"]
    if t.returncode == 2:
        why = (t.stderr.strip().splitlines() or ["?"])[0].replace("packsim: error: ", "")
        return [name, "skipped", why]
    h, hcpu = run(packsim, scenario, False, hh, None)
    if not os.path.exists(hh) or not os.path.exists(th):
        return [name, "failed", f"host exit {h.returncode}, target exit {t.returncode}: " + (t.stderr or h.stderr).strip()[:200]]
    hd, hc = events(hh)
    td, tc = events(th)
    first = next((f"host {a} / target {b}" for a, b in zip(hd, td) if a != b), None)
    if first is None and len(hd) != len(td):
        first = f"{len(hd)} host decisions, {len(td)} target"
    shift = max((abs(a[0] - b[0]) for a, b in zip(hc, tc)), default=0.0)
    if len(hc) != len(tc) and first is None:
        first = f"{len(hc)} host relay contacts, {len(tc)} target"
    worst, load, stack = target_figures(t.stdout)
    for p in (hh, th):
        os.remove(p)
    return [name, "same" if first is None else "DIFFERENT", first or "", trip(h.stdout), trip(t.stdout), worst, load,
            stack, f"{shift * 1e6:.1f}", f"{hcpu:.2f}", f"{tcpu:.2f}"]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("scenarios", nargs="*")
    ap.add_argument("--packsim", default=str(ROOT / "build" / "packsim"))
    ap.add_argument("--jobs", type=int, default=1)
    ap.add_argument("--out", default="")
    ap.add_argument("--timeout", type=float, default=None, help="wall seconds a target run may take")
    a = ap.parse_args()
    files = collect(a.scenarios or [ROOT / "scenarios"])
    head = ["scenario", "decisions", "first difference", "host trip", "target trip", "worst cycles per task",
            "CPU load %", "stack bytes", "relay contact shift us", "host CPU s", "target CPU s"]
    out = open(a.out, "w") if a.out else None
    print("\t".join(head), file=out or sys.stdout, flush=True)
    differ = False
    with tempfile.TemporaryDirectory() as tmp, cf.ThreadPoolExecutor(a.jobs) as ex:
        for row in ex.map(lambda f: compare(a.packsim, f.resolve(), tmp, a.timeout), files):
            differ = differ or row[1] in ("DIFFERENT", "failed")
            line = "\t".join(row)
            print(line, flush=True)
            if out:
                print(line, file=out, flush=True)
    return 1 if differ else 0


if __name__ == "__main__":
    sys.exit(main())
