#include "bench/bench_support.hpp"

#include <time.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>

#include "core/scenario/load_scenario.hpp"

namespace packsim::bench {

namespace {

double threadCpu_s() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

std::string scenarioPath(const std::string& file) { return std::string(PACKSIM_SCENARIO_DIR) + "/" + file; }

std::string list(const std::vector<double>& v) {
  std::ostringstream os;
  os.precision(17);
  os << '[';
  for (size_t i = 0; i < v.size(); ++i) os << (i ? ", " : "") << v[i];
  os << ']';
  return os.str();
}

}  // namespace

Timing measure(int repeats, const std::function<void()>& f) {
  Timing best{INFINITY, INFINITY};
  for (int r = 0; r < std::max(1, repeats); ++r) {
    const auto w0 = std::chrono::steady_clock::now();
    const double c0 = threadCpu_s();
    f();
    const double cpu = threadCpu_s() - c0;
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - w0).count();
    best.cpu_s = std::min(best.cpu_s, cpu);
    best.wall_s = std::min(best.wall_s, wall);
  }
  return best;
}

Scenario bundledScenario(const std::string& file, const Overrides& overrides) {
  return loadScenarioFileWithOverrides(scenarioPath(file), overrides);
}

Scenario scaledPack(int series, int parallel, double duration_s, const std::string& solver) {
  const Scenario d = bundledScenario("motorcycle_110s.yaml");
  const double p = parallel;
  std::vector<double> current(d.load.i_A);
  for (double& i : current) i *= p;
  std::vector<double> therm;
  for (const ThermistorSite& site : d.hardware.thermistor_sites)
    if (site.onCell() && site.cell < series) therm.push_back(site.cell + 1);
  // Boards of up to the bundled six devices (a small pack has fewer devices than that).
  const int devices = (series + d.hardware.afe.cells_per_device - 1) / d.hardware.afe.cells_per_device;
  const Overrides o = {
      {"pack.series", std::to_string(series)},
      {"hardware.afe.devices_per_board", std::to_string(std::min(d.hardware.afe.devices_per_board, devices))},
      {"pack.parallel", std::to_string(parallel)},
      {"pack.interconnect_ohm", fmt(1e-4 * series / p, 9)},
      {"hardware.thermistors.at_groups", list(therm)},
      {"hardware.current_sense.shunt_ohm", fmt(1e-4 / p, 12)},
      {"bms.protections.overcurrent_discharge", "{threshold_A: " + fmt(400 * p, 3) + ", hysteresis_A: " +
                                                    fmt(10 * p, 3) + ", delay_ms: 500}"},
      {"bms.protections.overcurrent_charge", "{threshold_A: " + fmt(120 * p, 3) + ", hysteresis_A: " +
                                                 fmt(5 * p, 3) + ", delay_ms: 500}"},
      {"load", "{points: {time_s: " + list(d.load.t_s) + ", current_A: " + list(current) +
                   "}, interpolation: linear, laps: 1000}"},
      {"run.duration_s", fmt(duration_s, 6)},
      {"run.solver", solver},
  };
  return bundledScenario("motorcycle_110s.yaml", o);
}

double loadAverage1() {
  double l[1] = {0.0};
  return getloadavg(l, 1) == 1 ? l[0] : -1.0;
}

std::string Table::str() const {
  std::vector<size_t> w;
  for (const auto& r : rows_)
    for (size_t i = 0; i < r.size(); ++i) {
      if (w.size() <= i) w.push_back(0);
      w[i] = std::max(w[i], r[i].size());
    }
  std::ostringstream os;
  for (size_t k = 0; k < rows_.size(); ++k) {
    const auto& r = rows_[k];
    for (size_t i = 0; i < r.size(); ++i) {
      os << r[i];
      if (i + 1 < r.size()) os << std::string(w[i] - r[i].size() + 2, ' ');
    }
    os << '\n';
    if (k == 0) {
      size_t total = 0;
      for (size_t x : w) total += x + 2;
      os << std::string(total - 2, '-') << '\n';
    }
  }
  return os.str();
}

std::string fmt(double v, int precision) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", precision, v);
  return buf;
}

}  // namespace packsim::bench
