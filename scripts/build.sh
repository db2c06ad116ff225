#!/usr/bin/env bash
# Configures and builds packsim into build/ (or $BUILD_DIR). Extra arguments go to CMake.
# TARGETS="packsim" builds only those targets (the README's first command: the executable
# and nothing else); by default every target (tests, bench, Python module) is built.
# Works with Debian's CMake 3.25 and with a pip-installed CMake 4.x (the policy floor
# lets CMake 4 read Debian's older package config files).
set -euo pipefail
cd "$(dirname "$0")/.."
# The project's .venv, which scripts/install-deps.sh makes where the system python3 is
# externally managed (Debian's): its python3 (and the packages in it) comes first.
if [ -x .venv/bin/python3 ]; then export PATH="$PWD/.venv/bin:$PATH"; fi
BUILD_DIR=${BUILD_DIR:-build}
GEN=(); command -v ninja >/dev/null 2>&1 && GEN=(-G Ninja)
# ccache (scripts/install-deps.sh installs it) when present: a second build dir or a fresh
# clone of the same sources compiles from its cache. Paths are hashed relative to this
# folder and without the build folder's name, so the sanitizer, test and CI builds of
# unchanged sources hit. PACKSIM_NO_CCACHE=1 turns it off.
LAUNCH=()
if command -v ccache >/dev/null 2>&1 && [ -z "${PACKSIM_NO_CCACHE:-}" ]; then
  export CCACHE_BASEDIR="$PWD" CCACHE_NOHASHDIR=1
  LAUNCH=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
fi
if [ ! -f "$BUILD_DIR/CMakeCache.txt" ]; then
  cmake -S . -B "$BUILD_DIR" "${GEN[@]}" -DCMAKE_POLICY_VERSION_MINIMUM=3.5 -DCMAKE_BUILD_TYPE=RelWithDebInfo "${LAUNCH[@]}" "$@"
elif [ $# -gt 0 ]; then
  cmake -S . -B "$BUILD_DIR" "$@"
fi
TARGET_ARGS=()
for t in ${TARGETS:-}; do TARGET_ARGS+=(--target "$t"); done
cmake --build "$BUILD_DIR" -j"${JOBS:-2}" "${TARGET_ARGS[@]}"
