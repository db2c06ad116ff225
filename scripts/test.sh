#!/usr/bin/env bash
# Builds and runs every test: the C++ suites (ctest), the BMS core cross-compiled for a
# Cortex-M4, a fuzz smoke of the input loaders (scripts/fuzz.sh, build-fuzz/), the whole
# C++ suite again under AddressSanitizer + UBSan in build-asan/, and the Python tests. PACKSIM_SKIP_SANITIZE=1 skips the sanitizer pass.
set -euo pipefail
cd "$(dirname "$0")/.."

# Wall time per stage, printed at the end (and so in CI's log), also after a failure.
STAGES=""
stage_name=""
stage_start=$SECONDS
close_stage() {
  [ -n "$stage_name" ] && STAGES+=$(printf '  %-50s %5d s' "$stage_name" $((SECONDS - stage_start)))$'\n'
  stage_name=""
}
stage() {  # stage NAME: closes the previous stage, opens NAME
  close_stage
  stage_name=$1
  stage_start=$SECONDS
  echo "== $1"
}
print_stages() {
  close_stage
  printf '== time per stage\n%s  %-50s %5d s\n' "$STAGES" total "$SECONDS"
}
trap print_stages EXIT

stage "build and C++ tests"
BUILD_DIR=build scripts/build.sh -DPACKSIM_BUILD_TESTS=ON
ctest --test-dir build -j2 --output-on-failure --timeout 600

echo "   (includes the firmware property tests, FirmwareProperties.*, the fault matrix, FaultMatrix.*, and"
echo "    every bundled scenario against its expect: block, Every/BundledScenario.*)"
# Every bundled scenario against its expect: block runs in the pass above, one test per
# file (Every/BundledScenario.PassesItsExpectBlock/*: checkScenarioFile on the files
# collectScenarioFiles finds, exactly what `packsim check scenarios` runs, with the same
# build). The command's own report and exit status are tested in Check.* and
# tests/python/test_check.py. A separate `build/packsim check scenarios` stage ran every
# one of them a second time (53-77 s of the test command on 2 cores).

stage "BMS core cross-compiled for Cortex-M4 (freestanding, no exceptions, no RTTI)"
bms/cross_check.sh build/bms-cortex-m4

stage "fuzz smoke: each loader harness, a fixed seed and input count, under libFuzzer + ASan + UBSan (build-fuzz/)"
scripts/fuzz.sh

if [ "${PACKSIM_SKIP_SANITIZE:-0}" != 1 ]; then
  stage "C++ tests under AddressSanitizer + UBSan"
  # Optimised (-O2 -g) so the sanitizers cost ~2-3x rather than the ~10x of -O0. The
  # `sanitize` label is every test but the solver-agreement sweep, which re-runs every
  # bundled scenario on CVODE: that plant code runs here under the fast-integrator tests,
  # and the sweep runs in the pass above (tests/CMakeLists.txt).
  BUILD_DIR=build-asan scripts/build.sh -DPACKSIM_BUILD_TESTS=ON -DPACKSIM_SANITIZE=ON -DPACKSIM_BUILD_BENCH=OFF \
    -DCMAKE_BUILD_TYPE=RelWithDebInfo
  ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
    ctest --test-dir build-asan -j2 --output-on-failure --timeout 1200 -L sanitize

fi

if [ -d tests/python ]; then
  stage "Python tests"
  PYTHONPATH="$PWD/build/python:$PWD/python${PYTHONPATH:+:$PYTHONPATH}" python3 -m pytest -q tests/python
fi
