#!/usr/bin/env bash
# Builds the benchmarks in Release (own build folder, build-bench/ or $BUILD_DIR) and
# prints every figure as one table. Arguments go to packsim_bench:
#   bench/run.sh                  everything (~3-5 minutes on 2 cores)
#   bench/run.sh --quick          shorter runs, fewer repeats (~1 minute)
#   bench/run.sh macro batch      selected benchmarks: floor, macro, scaling, batch
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR=${BUILD_DIR:-build-bench}
GEN=(); command -v ninja >/dev/null 2>&1 && GEN=(-G Ninja)
if [ ! -f "$BUILD_DIR/CMakeCache.txt" ]; then
  cmake -S . -B "$BUILD_DIR" "${GEN[@]}" -DCMAKE_POLICY_VERSION_MINIMUM=3.5 >/dev/null
fi
# Release every time: an existing cache may hold another build type.
cmake -S . -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=Release -DPACKSIM_BUILD_BENCH=ON >/dev/null
cmake --build "$BUILD_DIR" --target packsim_bench -j"${JOBS:-2}" >/dev/null
echo "$(date -I) | $(lscpu | sed -n 's/^Model name: *//p') | $(nproc) cores | packsim $(git rev-parse --short HEAD 2>/dev/null || echo '?')"
exec "$BUILD_DIR/packsim_bench" "$@"
