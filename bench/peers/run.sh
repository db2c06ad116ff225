#!/usr/bin/env bash
# packsim side by side with its peers, every figure from this one run (ratios between
# figures taken minutes apart on the same machine; no thresholds):
#   (1) PyBaMM's Thevenin model on the 1-cell race of common.py (same OCV table, R0, one
#       RC pair, same current), against packsim's fast and CVODE solvers;
#   (2) liionpack on a 16s4p pack of the same cell (Thevenin cells), against packsim.
# The peers live in their own virtual environment, bench/peers/.venv (created here from
# requirements.txt, git-ignored); the system Python only runs packsim.
#   bench/peers/run.sh                 # ~10-15 minutes on 2 busy cores (liionpack: most of it)
#   BUILD_DIR=build REPEATS=3 bench/peers/run.sh
# Writes bench/peers/results.json and prints a summary. The 1-cell race alone, with
# packsim builds and PyBaMM's solvers interleaved round by round (before/after a change):
#   bench/peers/.venv/bin/python bench/peers/one_cell.py --packsim main=OTHER/build/python \
#       --packsim now=build/python --json bench/peers/one_cell.json
set -euo pipefail
HERE="$(cd "$(dirname "$0")" && pwd)"
REPO="$(cd "$HERE/../.." && pwd)"
BUILD_DIR=${BUILD_DIR:-build}
case $BUILD_DIR in /*) ;; *) BUILD_DIR="$REPO/$BUILD_DIR" ;; esac
REPEATS=${REPEATS:-3}
PY=${PYTHON:-python3}

if [ ! -x "$HERE/.venv/bin/python" ]; then
  "$PY" -m venv "$HERE/.venv"
fi
if ! "$HERE/.venv/bin/python" -m pip install -q -r "$HERE/requirements.txt"; then
  echo "peers: could not install bench/peers/requirements.txt into bench/peers/.venv" >&2; exit 1
fi
if ! PYTHONPATH="$BUILD_DIR/python" "$PY" -c "import packsim._packsim" 2>/dev/null; then
  echo "peers: packsim is not built in $BUILD_DIR (scripts/build.sh, or set BUILD_DIR)" >&2; exit 1
fi

TMP=$(mktemp -d); trap 'rm -rf "$TMP"' EXIT
cd "$HERE"
PYTHONPATH="$BUILD_DIR/python" "$PY" packsim_side.py "$TMP/packsim.npz" "$REPEATS"
TQDM_DISABLE=1 "$HERE/.venv/bin/python" peers_side.py "$TMP/peers.npz" "$REPEATS"
"$PY" compare.py "$TMP/packsim.npz" "$TMP/peers.npz" "$HERE/results.json"
