#!/usr/bin/env bash
# Coverage-guided fuzzing of the input parsers (libFuzzer + ASan + UBSan, clang).
#
#   scripts/fuzz.sh                    # smoke (scripts/test.sh runs this): a fixed seed and a
#                                      # fixed number of inputs per harness (25-60 s of one
#                                      # core each, two harnesses at a time), so every run from
#                                      # the same corpus, CI's fresh one included, tries the
#                                      # very same inputs
#   FUZZ_SECONDS=900 scripts/fuzz.sh   # a campaign: 15 min per harness, a new seed each time
#   FUZZ_SECONDS=900 scripts/fuzz.sh fuzz_scenario    # one harness
#
# Builds into build-fuzz/ (clang, only the harnesses), seeds each harness's corpus from
# the bundled files (tests/fuzz/make_corpus.py) and replays tests/fuzz/regressions/
# first (every crash found so far; each also has a C++ regression test). The corpus
# grows in build-fuzz/corpus/<harness>; a crash leaves build-fuzz/crash-* and fails.
set -euo pipefail
cd "$(dirname "$0")/.."
SECONDS_PER=${FUZZ_SECONDS:-}
# Smoke budget per harness (inputs, not seconds: the same on any machine and load).
declare -A SMOKE_RUNS=([fuzz_scenario]=4000 [fuzz_csv_profile]=100000 [fuzz_sweep]=100000 [fuzz_overrides]=4000)
HARNESSES=("$@")
[ ${#HARNESSES[@]} -eq 0 ] && HARNESSES=(fuzz_scenario fuzz_overrides fuzz_csv_profile fuzz_sweep)  # the two slow ones first
BUILD=build-fuzz

# ccache as in scripts/build.sh: a fresh clone (CI's) compiles the instrumented libraries
# from the cache instead of from scratch (about 140 files, all of core/ bms/ models/).
LAUNCH=()
if command -v ccache >/dev/null 2>&1 && [ -z "${PACKSIM_NO_CCACHE:-}" ]; then
  export CCACHE_BASEDIR="$PWD" CCACHE_NOHASHDIR=1
  LAUNCH=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
fi
if [ ! -f "$BUILD/CMakeCache.txt" ]; then
  GEN=(); command -v ninja >/dev/null 2>&1 && GEN=(-G Ninja)
  CC=clang CXX=clang++ cmake -S . -B "$BUILD" "${GEN[@]}" -DCMAKE_POLICY_VERSION_MINIMUM=3.5 \
    -DCMAKE_BUILD_TYPE=RelWithDebInfo -DPACKSIM_BUILD_FUZZ=ON -DPACKSIM_BUILD_TESTS=OFF \
    -DPACKSIM_BUILD_BENCH=OFF -DPACKSIM_BUILD_PYTHON=OFF "${LAUNCH[@]}" >/dev/null
fi
cmake --build "$BUILD" -j"${JOBS:-2}" --target "${HARNESSES[@]}"
python3 tests/fuzz/make_corpus.py "$BUILD/corpus"

export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
run_harness() {  # run_harness H: its regressions, then its budget; prints a summary, fails on a crash
  local h=$1 budget what reg
  if [ -n "$SECONDS_PER" ]; then
    budget=(-max_total_time="$SECONDS_PER"); what="${SECONDS_PER} s of fuzzing"
  else
    budget=(-seed=1 -runs="${SMOKE_RUNS[$h]:-10000}"); what="${SMOKE_RUNS[$h]:-10000} inputs (seed 1)"
  fi
  echo "== $h: regressions, then $what"
  reg=tests/fuzz/regressions/$h
  if [ -d "$reg" ] && [ -n "$(ls -A "$reg")" ]; then
    "$BUILD/fuzz/$h" -runs=0 "$reg"/* > "$BUILD/fuzz-$h-regressions.log" 2>&1 || {
      tail -40 "$BUILD/fuzz-$h-regressions.log"; echo "fuzz: $h fails on a regression input ($reg)"; return 1; }
    grep "^Executed" "$BUILD/fuzz-$h-regressions.log"
  fi
  mkdir -p "$BUILD/corpus/$h"
  (cd "$BUILD" && "fuzz/$h" "${budget[@]}" -timeout=10 -rss_limit_mb=2048 \
     -max_len=16384 -print_final_stats=1 "corpus/$h" 2> "fuzz-$h.log") || {
    tail -40 "$BUILD/fuzz-$h.log"; echo "fuzz: $h found a crash (see $BUILD/crash-*)"; return 1; }
  grep -E "stat::number_of_executed_units|stat::new_units_added" "$BUILD/fuzz-$h.log" | tr '\n' ' '; echo
}
# Each harness is one process: JOBS (2) of them at a time, so the smoke takes the time of
# its slowest pair rather than of all four in a row; the summaries print in order.
rm -f "$BUILD"/fuzz-*.status
for h in "${HARNESSES[@]}"; do
  while [ "$(jobs -rp | wc -l)" -ge "${JOBS:-2}" ]; do wait -n || true; done
  ( st=0; run_harness "$h" || st=1; echo "$st" > "$BUILD/fuzz-$h.status" ) > "$BUILD/fuzz-$h.summary" 2>&1 &
done
wait
failed=0
for h in "${HARNESSES[@]}"; do
  cat "$BUILD/fuzz-$h.summary"
  [ "$(cat "$BUILD/fuzz-$h.status" 2>/dev/null)" = 0 ] || failed=1
done
exit $failed
