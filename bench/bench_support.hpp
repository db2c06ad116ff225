// Shared pieces of the benchmarks: clocks, repetition, the scenarios they run and the
// table they print.
//
// Timing on a shared machine: every figure is taken as thread CPU time (what the run
// itself consumed, unaffected by other processes waiting for the same cores) and as
// wall time; each measurement is repeated and the minimum kept. Ratios are always
// formed between figures measured in the same process.
#pragma once
#include <functional>
#include <string>
#include <vector>

#include "core/scenario/overrides.hpp"
#include "core/scenario/scenario.hpp"

namespace packsim::bench {

struct Timing {
  double cpu_s = 0.0;   // thread CPU time
  double wall_s = 0.0;
};

// Runs f `repeats` times; returns the minimum CPU and the minimum wall time.
Timing measure(int repeats, const std::function<void()>& f);

// A bundled scenario (scenarios/<file>) with overrides applied.
Scenario bundledScenario(const std::string& file, const Overrides& overrides = {});

// Pack of series × parallel cells of system D (motorcycle_110s: nmc_40Ah cells, its
// road-race lap, 10 ms tick, 1 Hz recording), for the scaling benchmark. The lap
// current, the current sensor range and the over-current thresholds scale with the
// parallel count so every cell sees the same C-rate; thermistors stay on cells the
// pack has. `duration_s` of racing; `solver` "cvode" or "fast".
Scenario scaledPack(int series, int parallel, double duration_s, const std::string& solver);

// Load average over the last minute (how busy the shared machine is).
double loadAverage1();

// A plain text table: a header row, then rows; columns padded to their widest cell.
class Table {
 public:
  explicit Table(std::vector<std::string> header) : rows_{std::move(header)} {}
  void add(std::vector<std::string> row) { rows_.push_back(std::move(row)); }
  std::string str() const;

 private:
  std::vector<std::vector<std::string>> rows_;
};

std::string fmt(double v, int precision);

}  // namespace packsim::bench
