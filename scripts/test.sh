#!/usr/bin/env bash
# Builds and runs every test: the C++ suites (ctest), the BMS core cross-compiled for a
# Cortex-M4, a fuzz smoke of the input loaders (scripts/fuzz.sh, build-fuzz/), the
# C++ suites again under AddressSanitizer + UBSan in build-asan/ (the `sanitize` label: the quick
# tests and a few short physics tests), and the Python tests. PACKSIM_SKIP_SANITIZE=1 skips the sanitizer pass.
set -euo pipefail
cd "$(dirname "$0")/.."
# The project's .venv, which scripts/install-deps.sh makes where the system python3 is
# externally managed (Debian's): its python3 (and the packages in it) comes first.
if [ -x .venv/bin/python3 ]; then export PATH="$PWD/.venv/bin:$PATH"; fi

# Wall and CPU time (user + sys of every process the stage ran) per stage, printed at the
# end (and so in CI's log), also after a failure. On a shared machine the wall time says
# little; the CPU time divided by the cores is what the stage costs an idle machine.
STAGES=""
stage_name=""
stage_start=$SECONDS
TIMES_FILE=$(mktemp)
CPU=0
cpu_now() {  # CPU=seconds of this shell and of every child it has waited for (bash's `times`,
  times > "$TIMES_FILE"  # run here: in a subshell or a pipe it reports the subshell's own, empty, times)
  CPU=$(awk '{ for (i = 1; i <= 2; i++) { split($i, a, "m"); s += a[1] * 60 + a[2] } } END { printf "%.0f", s }' "$TIMES_FILE")
}
stage_cpu=0
close_stage() {
  cpu_now
  [ -n "$stage_name" ] && STAGES+=$(printf '  %-50s %5d s wall %6d s CPU' "$stage_name" $((SECONDS - stage_start)) \
                                      $((CPU - stage_cpu)))$'\n'
  stage_name=""
}
stage() {  # stage NAME: closes the previous stage, opens NAME
  close_stage
  stage_name=$1
  stage_start=$SECONDS
  stage_cpu=$CPU
  echo "== $1"
}
print_stages() {
  close_stage
  printf '== time per stage\n%s  %-50s %5d s wall %6d s CPU\n' "$STAGES" total "$SECONDS" "$CPU"
  rm -f "$TIMES_FILE"
}
trap print_stages EXIT
slowest_tests() {  # slowest_tests BUILD_DIR: the ten longest tests of its last ctest run
  local log=$1/Testing/Temporary/LastTest.log
  [ -f "$log" ] || return 0
  echo "   slowest tests (wall s, two at a time):"
  awk '/^[0-9]+\/[0-9]+ Test: /{ name = $3 } /^Test time = /{ printf "   %8.1f  %s\n", $4, name }' "$log" |
    sort -rn | awk 'NR <= 10'  # (awk reads to the end: `head` could stop sort with SIGPIPE)
}

# The builds (build/, build-asan/, build-fuzz/) and the tests' files take about 4.5 GB: on a
# fuller disk the suite fails late, as writes that fail in unrelated tests, so say it first.
free_kb=$(df -Pk . "${TMPDIR:-/tmp}" | awk 'NR > 1 { if (min == "" || $4 < min) min = $4 } END { print min }')
if [ -n "$free_kb" ] && [ "$free_kb" -lt 4718592 ]; then
  echo "warning: $((free_kb / 1048576)) GB free on this checkout's or the temp folder's disk; a full test run needs about 4.5 GB" >&2
fi

stage "build and C++ tests"
BUILD_DIR=build scripts/build.sh -DPACKSIM_BUILD_TESTS=ON
ctest --test-dir build -j2 --output-on-failure --timeout 600
slowest_tests build

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
  # `sanitize` label is the quick tests of these executables plus a handful of short
  # `physics` tests (tests/CMakeLists.txt, PACKSIM_SANITIZE_PHYSICS_TESTS) chosen by line
  # coverage: they reach all the lines of core/ models/ bms/ the whole physics set reaches
  # but the few docs/hardening.md lists ("What the sanitizer pass leaves out"); the long
  # physics runs run once, unsanitized, in the pass above.
  # Only the executables the `sanitize` tests run (and what core_tests starts: the packsim
  # program and the firmware libraries), not the FMU library, target_tests or the bench.
  TARGETS="bms_tests model_tests core_tests ltc681x_tests" BUILD_DIR=build-asan scripts/build.sh \
    -DPACKSIM_BUILD_TESTS=ON -DPACKSIM_SANITIZE=ON -DPACKSIM_BUILD_BENCH=OFF -DCMAKE_BUILD_TYPE=RelWithDebInfo
  ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
    ctest --test-dir build-asan -j2 --output-on-failure --timeout 1200 -L sanitize
  slowest_tests build-asan

fi

if [ -d tests/python ]; then
  stage "Python tests"
  # Two worker processes (pytest-xdist), as ctest runs two tests at once: the same work
  # split over 2 cores (2026-11-26: 252 s of CPU with two workers, 245 s with one, one
  # worker's share 119-137 s), so on an idle machine about half the wall time of one
  # process. `loadgroup` keeps the tests of a module that share a module-scoped fixture
  # on one worker, so it is built once (tests/python/conftest.py); every other test goes
  # to the free worker.
  # Not `-n auto`: more workers on a bigger machine would each repeat the session
  # fixtures and start their own kernels, browsers and Dask clusters for little gain.
  # Plain `python3 -m pytest tests/python` (one process) runs the same tests.
  XDIST=(-n 2 --dist loadgroup)
  if ! python3 -c "import xdist" 2>/dev/null; then
    echo "   pytest-xdist is not installed (scripts/install-deps.sh installs it): the Python tests run in one process"
    XDIST=()
  fi
  PYTHONPATH="$PWD/build/python:$PWD/python${PYTHONPATH:+:$PYTHONPATH}" python3 -m pytest -q "${XDIST[@]}" --durations=10 tests/python
fi
