#!/usr/bin/env python3
"""Proves "behaviour unchanged": runs every bundled scenario with two packsim binaries
and compares the result files bit for bit.

    scripts/compare_results.py --base OLD_PACKSIM [--new build/packsim]
    scripts/compare_results.py --base-ref main     [--new build/packsim]
    scripts/compare_results.py --base OLD --base-scenarios OLD_TREE/scenarios   (renamed keys)

--base-ref builds that git ref's `packsim` in a detached git worktree under the work
folder first (with ccache when installed). Without --workdir the worktree is removed
at the end; with --workdir it is kept, and a second run reuses its build (remove it
with `git worktree remove --force DIR/tree-REF`).

For each scenario (scenarios/**/*.yaml as `packsim check` collects them: not cells/ or
profiles/) both binaries run it with the same file and seed; then every group,
dataset and attribute of the two HDF5 files is compared: dataset dtype, shape and raw
bytes (so NaN payloads and signed zeros count), compound datasets field by field,
object references by the path they point at, and the printed run summary. One line per
scenario; exit status 1 on any difference, 2 if a run fails on one side only.

Attributes expected to differ between builds are ignored, and only these:
"""
import argparse
import atexit
import os
import re
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

import h5py
import numpy as np

# (object path, attribute name) pairs that may differ between two builds.
IGNORED_ATTRS = {
    ("/", "packsim_version"),  # the version string of the build
}
__doc__ += "".join(f"    {obj} @{name}\n" for obj, name in sorted(IGNORED_ATTRS))

REPO = Path(__file__).resolve().parent.parent


def bundled_scenarios(root):
    """The files `packsim check` runs (core/check/check.cpp collectScenarioFiles)."""
    found = []
    for dirpath, dirnames, filenames in os.walk(root):
        dirnames[:] = [d for d in dirnames if d not in ("cells", "profiles")]
        found += [os.path.join(dirpath, f) for f in filenames if f.endswith(".yaml")]
    return sorted(found)


def build_ref(ref, workdir):
    """Builds `packsim` of a git ref in a temporary worktree; returns the binary."""
    tree = workdir / f"tree-{re.sub(r'[^A-Za-z0-9._-]', '_', ref)}"
    if not tree.exists():
        subprocess.run(["git", "-C", str(REPO), "worktree", "add", "--detach", str(tree), ref], check=True)
    build = tree / "build"
    if not (build / "CMakeCache.txt").exists():
        gen = ["-G", "Ninja"] if shutil.which("ninja") else []
        cache = ["-DCMAKE_CXX_COMPILER_LAUNCHER=ccache", "-DCMAKE_C_COMPILER_LAUNCHER=ccache"] \
            if shutil.which("ccache") else []
        subprocess.run(["cmake", "-S", str(tree), "-B", str(build), *gen, *cache, "-DCMAKE_POLICY_VERSION_MINIMUM=3.5",
                        "-DCMAKE_BUILD_TYPE=RelWithDebInfo"], check=True)
    subprocess.run(["cmake", "--build", str(build), "-j", os.environ.get("JOBS", "2"), "--target", "packsim"],
                   check=True)
    return build / "packsim"


def run(binary, scenario, out):
    """Runs one scenario; returns (ok, printed summary with the result path masked)."""
    p = subprocess.run([str(binary), "run", scenario, "-o", str(out)], capture_output=True, text=True)
    text = (p.stdout + p.stderr).replace(str(out), "<result>")
    return p.returncode == 0 and out.exists(), text


def comparable(value, f):
    """An attribute or dataset value as something == can compare bit for bit."""
    if isinstance(value, h5py.Reference):
        return ("ref", f[value].name if value else None)
    if isinstance(value, np.ndarray):
        if value.dtype.names:  # compound: field by field
            return ("compound", value.dtype.descr, tuple(comparable(value[n], f) for n in value.dtype.names))
        if value.dtype.kind == "O":
            return ("objects", value.shape, tuple(comparable(v, f) for v in value.ravel()))
        return ("array", value.dtype.str, value.shape, np.ascontiguousarray(value).tobytes())
    if isinstance(value, np.generic):
        return ("scalar", value.dtype.str, value.tobytes())
    if isinstance(value, bytes):
        return ("bytes", value)
    return (type(value).__name__, value)


def objects(f):
    found = {"/": f}
    f.visititems(lambda name, obj: found.__setitem__("/" + name, obj))
    return found


def compare_files(a_path, b_path):
    """Differences between two result files, as short sentences."""
    diffs = []
    with h5py.File(a_path, "r") as a, h5py.File(b_path, "r") as b:
        oa, ob = objects(a), objects(b)
        for name in sorted(set(oa) ^ set(ob)):
            diffs.append(f"{name} only in {'base' if name in oa else 'new'}")
        for name in sorted(set(oa) & set(ob)):
            x, y = oa[name], ob[name]
            if type(x) is not type(y):
                diffs.append(f"{name}: a {type(x).__name__} against a {type(y).__name__}")
                continue
            if isinstance(x, h5py.Dataset):
                if x.dtype != y.dtype or x.shape != y.shape:
                    diffs.append(f"{name}: {x.dtype}{x.shape} against {y.dtype}{y.shape}")
                elif comparable(x[()], a) != comparable(y[()], b):
                    diffs.append(f"{name}: values differ" + first_difference(x[()], y[()]))
            for attr in sorted(set(x.attrs) | set(y.attrs)):
                if (name, attr) in IGNORED_ATTRS:
                    continue
                if attr not in x.attrs or attr not in y.attrs:
                    diffs.append(f"{name} @{attr} only in {'base' if attr in x.attrs else 'new'}")
                elif comparable(x.attrs[attr], a) != comparable(y.attrs[attr], b):
                    diffs.append(f"{name} @{attr}: {short(x.attrs[attr])} against {short(y.attrs[attr])}")
    return diffs


def first_difference(x, y):
    """Where two datasets of the same dtype and shape first differ (a description only)."""
    if not isinstance(x, np.ndarray) or x.dtype.names or x.dtype.kind == "O":
        for i, (p, q) in enumerate(zip(np.ravel(x), np.ravel(y))):
            if repr(p) != repr(q):
                return f" (first at element {i}: {short(p)} against {short(q)})"
        return ""
    width = x.dtype.itemsize
    xb = np.frombuffer(np.ascontiguousarray(x).tobytes(), np.uint8).reshape(-1, width)
    yb = np.frombuffer(np.ascontiguousarray(y).tobytes(), np.uint8).reshape(-1, width)
    bad = np.flatnonzero((xb != yb).any(axis=1))
    if not bad.size:
        return ""
    i = int(bad[0])
    return f" (first at flat index {i}: {x.ravel()[i]!r} against {y.ravel()[i]!r}; {bad.size} elements)"


def short(v):
    s = repr(v)
    return s if len(s) < 80 else s[:77] + "..."


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    base = ap.add_mutually_exclusive_group(required=True)
    base.add_argument("--base", help="the packsim binary to compare against")
    base.add_argument("--base-ref", help="a git ref whose packsim is built in a temporary worktree")
    ap.add_argument("--new", default=str(REPO / "build" / "packsim"), help="the packsim binary under test")
    ap.add_argument("--scenarios", default=str(REPO / "scenarios"), help="folder of scenarios (default: bundled)")
    ap.add_argument("--base-scenarios", help="the base binary runs each scenario from this folder instead (same "
                    "relative path): scenarios whose keys were renamed")
    ap.add_argument("--only", action="append", default=[], help="run only scenarios whose path contains this")
    ap.add_argument("--workdir", help="keep results (and a --base-ref build) here instead of a temporary folder")
    args = ap.parse_args()

    workdir = Path(args.workdir) if args.workdir else Path(tempfile.mkdtemp(prefix="packsim-compare-"))
    workdir.mkdir(parents=True, exist_ok=True)
    if not args.base:
        base_bin = build_ref(args.base_ref, workdir)
        if not args.workdir:  # a temporary build: drop its worktree when done
            atexit.register(subprocess.run, ["git", "-C", str(REPO), "worktree", "remove", "--force",
                                             str(base_bin.parent.parent)], check=False)
    else:
        base_bin = Path(args.base)
    new_bin = Path(args.new)
    for b in (base_bin, new_bin):
        if not os.access(b, os.X_OK):
            sys.exit(f"compare_results: {b} is not an executable packsim")
    scenarios = [s for s in bundled_scenarios(args.scenarios) if not args.only or any(o in s for o in args.only)]
    if not scenarios:
        sys.exit(f"compare_results: no scenarios under {args.scenarios}")
    print(f"base {base_bin}\nnew  {new_bin}\n{len(scenarios)} scenarios, results in {workdir}")

    status = 0
    for i, scen in enumerate(scenarios):
        rel = os.path.relpath(scen, args.scenarios)
        outs = [workdir / f"{i:03d}-{side}.h5" for side in ("base", "new")]
        for o in outs:
            o.unlink(missing_ok=True)
        base_scen = os.path.join(args.base_scenarios, rel) if args.base_scenarios else scen
        (ok_a, text_a), (ok_b, text_b) = run(base_bin, base_scen, outs[0]), run(new_bin, scen, outs[1])
        if args.base_scenarios:
            text_a = text_a.replace(os.path.abspath(args.base_scenarios), os.path.abspath(args.scenarios))
        if not ok_a or not ok_b:
            same_failure = not ok_a and not ok_b and text_a == text_b
            print(f"{'SAME ' if same_failure else 'FAIL '} {rel}: run failed on "
                  f"{'both sides alike' if same_failure else 'base' if not ok_a else 'new'}")
            if not same_failure:
                print("      " + (text_b if ok_a else text_a).strip().replace("\n", "\n      "))
                status = max(status, 2)
            continue
        diffs = compare_files(outs[0], outs[1])
        if text_a != text_b:
            diffs.append("printed summary differs")
        if diffs:
            status = max(status, 1)
            print(f"DIFF  {rel}: {len(diffs)} difference(s)")
            for d in diffs[:20]:
                print(f"      {d}")
        else:
            print(f"SAME  {rel}")
    print("bit-identical" if status == 0 else "DIFFERENT")
    return status


if __name__ == "__main__":
    sys.exit(main())
