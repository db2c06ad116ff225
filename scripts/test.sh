#!/usr/bin/env bash
# Builds and runs every test: the C++ suites (ctest), the BMS core cross-compiled for a
# Cortex-M4, a fuzz smoke of the input loaders (scripts/fuzz.sh, build-fuzz/), the whole
# C++ suite again under AddressSanitizer + UBSan in build-asan/, and the Python tests. PACKSIM_SKIP_SANITIZE=1 skips the sanitizer pass.
set -euo pipefail
cd "$(dirname "$0")/.."

echo "== build and C++ tests"
BUILD_DIR=build scripts/build.sh -DPACKSIM_BUILD_TESTS=ON
ctest --test-dir build -j2 --output-on-failure --timeout 600

echo "   (includes the firmware property tests, FirmwareProperties.*, and the fault matrix, FaultMatrix.*)"

echo "== every bundled scenario against its expect: block"
build/packsim check scenarios

echo "== BMS core cross-compiled for Cortex-M4 (freestanding, no exceptions, no RTTI)"
bms/cross_check.sh build/bms-cortex-m4

echo "== fuzz smoke: each loader harness, a fixed seed and input count, under libFuzzer + ASan + UBSan (build-fuzz/)"
scripts/fuzz.sh

if [ "${PACKSIM_SKIP_SANITIZE:-0}" != 1 ]; then
  echo "== C++ tests under AddressSanitizer + UBSan"
  # Optimised (-O2 -g) so the sanitizers cost ~2-3x rather than the ~10x of -O0. The
  # solver-agreement sweep re-runs every bundled scenario with a second integrator
  # already covered here by the fast-integrator tests: it runs in the pass above only.
  BUILD_DIR=build-asan scripts/build.sh -DPACKSIM_BUILD_TESTS=ON -DPACKSIM_SANITIZE=ON -DPACKSIM_BUILD_BENCH=OFF \
    -DCMAKE_BUILD_TYPE=RelWithDebInfo
  ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
    ctest --test-dir build-asan -j2 --output-on-failure --timeout 1200 -E 'SolverAgreement\.'

fi

if [ -d tests/python ]; then
  echo "== Python tests"
  PYTHONPATH="$PWD/build/python:$PWD/python${PYTHONPATH:+:$PYTHONPATH}" python3 -m pytest -q tests/python
fi
