#!/usr/bin/env bash
# Coverage-guided fuzzing of the input parsers (libFuzzer + ASan + UBSan, clang).
#
#   scripts/fuzz.sh                    # smoke (scripts/test.sh runs this): a fixed seed and a
#                                      # fixed number of inputs per harness (about 30 s each),
#                                      # so every run, CI's included, tries the very same inputs
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
[ ${#HARNESSES[@]} -eq 0 ] && HARNESSES=(fuzz_scenario fuzz_csv_profile fuzz_sweep fuzz_overrides)
BUILD=build-fuzz

if [ ! -f "$BUILD/CMakeCache.txt" ]; then
  GEN=(); command -v ninja >/dev/null 2>&1 && GEN=(-G Ninja)
  CC=clang CXX=clang++ cmake -S . -B "$BUILD" "${GEN[@]}" -DCMAKE_POLICY_VERSION_MINIMUM=3.5 \
    -DCMAKE_BUILD_TYPE=RelWithDebInfo -DPACKSIM_BUILD_FUZZ=ON -DPACKSIM_BUILD_TESTS=OFF \
    -DPACKSIM_BUILD_BENCH=OFF -DPACKSIM_BUILD_PYTHON=OFF >/dev/null
fi
cmake --build "$BUILD" -j"${JOBS:-2}" --target "${HARNESSES[@]}"
python3 tests/fuzz/make_corpus.py "$BUILD/corpus"

export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
for h in "${HARNESSES[@]}"; do
  if [ -n "$SECONDS_PER" ]; then
    budget=(-max_total_time="$SECONDS_PER"); what="${SECONDS_PER} s of fuzzing"
  else
    budget=(-seed=1 -runs="${SMOKE_RUNS[$h]:-10000}"); what="${SMOKE_RUNS[$h]:-10000} inputs (seed 1)"
  fi
  echo "== $h: regressions, then $what"
  reg=tests/fuzz/regressions/$h
  if [ -d "$reg" ] && [ -n "$(ls -A "$reg")" ]; then
    "$BUILD/fuzz/$h" -runs=0 "$reg"/* 2>&1 | grep "^Executed"
  fi
  mkdir -p "$BUILD/corpus/$h"
  (cd "$BUILD" && "fuzz/$h" "${budget[@]}" -timeout=10 -rss_limit_mb=2048 \
     -max_len=16384 -print_final_stats=1 "corpus/$h" 2> "fuzz-$h.log") || {
    tail -40 "$BUILD/fuzz-$h.log"; echo "fuzz: $h found a crash (see $BUILD/crash-*)"; exit 1; }
  grep -E "stat::number_of_executed_units|stat::new_units_added" "$BUILD/fuzz-$h.log" | tr '\n' ' '; echo
done
