// The fast integrator against the CVODE reference on every bundled scenario
// (scenarios/**/*.yaml but the cell sets, so a new preset or fault scenario is covered
// the moment it lands).
//
// Tolerances, and why:
//   cell voltage   2 mV   -- under one LSB of the coarsest bundled cell ADC (0.38 mV
//                            LSB + 0.5-1 mV noise ⇒ a BMS cannot tell 2 mV apart
//                            within a few samples); the fast scheme is exact for the
//                            RC branches at held current, so what remains is CVODE's
//                            own error and the explicit SOC/thermal update. The
//                            reference runs at rtol <= 1e-7: at the default 1e-6 CVODE's
//                            own SOC error reaches ~1e-4 on the scooter ride (a power
//                            load restarting it at every profile step; measured against
//                            rtol 1e-9), and the test is about the fast scheme's error.
//   SOC            1e-4   -- 0.01 % of capacity, far below any SOC estimator's error.
//   temperature    0.05 K -- half the BMS's 0.1 °C reading resolution.
//   trip           same decision and same reasons; time within 2 ticks + 0.5 s. A
//                  voltage trip fires when a noisy, quantised reading stays past the
//                  threshold for the debounce time; a sub-millivolt difference can
//                  move the first violating sample by a tick or two on a slowly
//                  sagging cell, so the bound allows that and nothing more.
//   active balancer -- its converters are bang-bang: each tick the controller picks the
//                  highest and lowest module from noisy readings, and a sub-mV difference
//                  between the two runs can flip a choice for a tick or two. One tick of a
//                  3 A converter moves a 3p module's terminal voltage by I·R ≈ 45 mV and
//                  its SOC by ~1e-4. On the team's 2.5 F bus the bus voltage, which the
//                  controller also switches on, swings by volts within a few ticks, so
//                  the two runs soon decide differently. There a cell's voltage is
//                  compared only at samples where both runs had its module's converter
//                  in the same state (same decision, same physics: 2 mV), the SOC to
//                  1e-3 (where the charge went, ten ticks of one converter). System B's
//                  race is compared whole (85 minutes, ~51,000 CVODE restarts: a
//                  converter switches at nearly every tick): on the diagonal Newton
//                  matrix (run.jacobian, set here) and with the bus carried as its
//                  square (OdeSystem::squaredState) CVODE takes ~2 steps a restart, and
//                  at this test's rtol 1e-7 the race costs it ~14 s of CPU, the fast
//                  integrator ~5 s (2026-11-26; before the squared bus ~52 s).
//                  Everything else is held to the bounds above.
// Samples are compared at equal times up to the first trip of either run (after a
// trip, a one-tick difference in opening time shifts the whole tail by one tick).
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <string>
#include <vector>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>

#include "core/sim/simulation.hpp"
#include "test_support.hpp"

namespace packsim {
namespace {

namespace fs = std::filesystem;

constexpr double kVoltageTol_V = 2e-3;
constexpr double kSocTol = 1e-4;
constexpr double kTempTol_K = 0.05;
constexpr double kTripTolTicks = 2.0;
constexpr double kTripTolExtra_s = 0.5;
constexpr double kActiveSocTol = 1e-3;
// A small pack (the 4s3p proof of concept, 3 cells a module) over its first 150 s: with
// ten times less charge per module, a converter pulse that one solver gives a tick
// earlier moves its modules' SOC enough that later samples of equal converter states
// no longer hold the same charge (over 1,200 s: 46 mV apart, 2026-11-26); the 150 s hold
// the bus precharge and every converter state.
constexpr double kActiveSmallCompare_s = 150.0;
// A large pack's balancer race (system B) is compared whole, to its trip.
// A vehicle race of a large pack (system B's 420 cells) on CVODE: the first hour holds the
// start, the hills with regeneration and the array's input; the rest repeats them (the
// whole 140 km stage ran past a minute). Small packs race to their end (and their trip).
constexpr double kVehicleCompare_s = 3600.0;

struct Differences {
  double voltage_V = 0.0, soc = 0.0, temp_K = 0.0, trip_s = 0.0;
  size_t samples = 0;
};

Differences compare(const RunResult& a, const RunResult& b) {
  Differences d;
  double until = INFINITY;
  if (a.summary.tripped) until = std::min(until, a.summary.trip_time_s);
  if (b.summary.tripped) until = std::min(until, b.summary.trip_time_s);
  const bool sameTrip = a.summary.tripped == b.summary.tripped &&
                        (!a.summary.tripped || a.summary.trip_time_s == b.summary.trip_time_s);
  const Recording& ra = a.rec;
  const Recording& rb = b.rec;
  const size_t cells = static_cast<size_t>(ra.cells);
  const bool converters = !ra.balancer_bus_V.empty() && !rb.balancer_bus_V.empty();
  const size_t series = converters ? ra.balance_current_A.size() / ra.samples() : 0, perGroup = series ? cells / series : 1;
  size_t j = 0;
  for (size_t i = 0; i < ra.samples(); ++i) {
    const double t = ra.time_s[i];
    if (!sameTrip && t >= until) break;
    while (j < rb.samples() && rb.time_s[j] < t - 1e-9) ++j;
    if (j >= rb.samples() || std::fabs(rb.time_s[j] - t) > 1e-9) continue;
    for (size_t c = 0; c < cells; ++c) {
      const size_t ia = i * cells + c, ib = j * cells + c;
      const size_t g = c / perGroup;
      const bool sameDecision =
          !converters || ra.balance_current_A[i * series + g] == rb.balance_current_A[j * series + g];
      if (sameDecision) d.voltage_V = std::max(d.voltage_V, std::fabs(ra.cell_voltage_V[ia] - rb.cell_voltage_V[ib]));
      d.soc = std::max(d.soc, std::fabs(ra.cell_soc[ia] - rb.cell_soc[ib]));
      d.temp_K = std::max(d.temp_K, std::fabs(ra.cell_temp_C[ia] - rb.cell_temp_C[ib]));
    }
    ++d.samples;
  }
  if (a.summary.tripped && b.summary.tripped) d.trip_s = std::fabs(a.summary.trip_time_s - b.summary.trip_time_s);
  return d;
}

// One test per bundled scenario (a loop over all of them ran 100 s on two cores).
std::vector<std::string> bundledScenarios() {
  std::map<std::string, fs::path> files;  // sorted: a stable order
  for (const auto& e : fs::recursive_directory_iterator(PACKSIM_SCENARIO_DIR)) {
    const fs::path rel = fs::relative(e.path(), PACKSIM_SCENARIO_DIR);
    if (e.path().extension() == ".yaml" && *rel.begin() != "cells") files[rel.string()] = e.path();
  }
  std::vector<std::string> out;
  for (const auto& f : files) out.push_back(f.first);
  return out;
}

std::string testName(const ::testing::TestParamInfo<std::string>& info) {
  std::string n = info.param.substr(0, info.param.size() - 5);  // without .yaml
  for (char& ch : n)
    if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
  return n;
}

class SolverAgreement : public ::testing::TestWithParam<std::string> {};

TEST_P(SolverAgreement, FastMatchesCvode) {
  const std::string name = GetParam();
  Scenario s = loadScenarioFile(test::scenarioDir() + "/" + name);
  const bool bangBang = s.hardware.active_balancer.present;
  if (bangBang && s.pack.series * s.pack.parallel < 100) s.run.duration_s = std::min(s.endTime_s(), kActiveSmallCompare_s);
  if (s.vehicle.present && s.pack.series * s.pack.parallel >= 100) s.run.duration_s = std::min(s.endTime_s(), kVehicleCompare_s);
  s.compare_scenario.clear();  // the `compare:` reference race is not what this test compares
  s.run.solver = RunConfig::Solver::Cvode;
  // Restarts ~10 times a second: a large pack's race takes the diagonal Newton matrix
  // (core/sim/cvode_integrator.hpp); the 4s3p proof-of-concept pack, cheap either way,
  // the sparse one it always ran on.
  if (bangBang && s.pack.series * s.pack.parallel >= 100) s.run.jacobian = RunConfig::Jacobian::Diagonal;
  const double scenarioRtol = s.run.rtol;
  s.run.rtol = std::min(scenarioRtol, 1e-7);
  const RunResult ref = runScenario(s);
  s.run.rtol = scenarioRtol;
  s.run.solver = RunConfig::Solver::Fast;
  const RunResult fast = runScenario(s);
  const Differences d = compare(ref, fast);
  std::printf("%-34s dV %.4f mV  dSOC %.2e  dT %.2e K  dtrip %.3f s  %zu samples\n", name.c_str(), d.voltage_V * 1e3,
              d.soc, d.temp_K, d.trip_s, d.samples);
  const double vTol = kVoltageTol_V;
  const double socTol = bangBang ? kActiveSocTol : kSocTol;
  EXPECT_GT(d.samples, 1u);
  EXPECT_LE(d.voltage_V, vTol);
  EXPECT_LE(d.soc, socTol);
  EXPECT_LE(d.temp_K, kTempTol_K);
  ASSERT_EQ(ref.summary.tripped, fast.summary.tripped);
  if (ref.summary.tripped) {
    EXPECT_EQ(ref.summary.trip_reason, fast.summary.trip_reason);
    EXPECT_LE(d.trip_s, kTripTolTicks * s.bms.tick_s + kTripTolExtra_s);
  }
  EXPECT_NEAR(ref.summary.final_soc_min, fast.summary.final_soc_min, socTol);
  EXPECT_NEAR(ref.summary.energy_delivered_Wh, fast.summary.energy_delivered_Wh,
              1e-3 * std::max(1.0, std::fabs(ref.summary.energy_delivered_Wh)));
}

// The suite is named so that `ctest -E '^SolverAgreement'` (the sanitizer pass) skips it.
INSTANTIATE_TEST_SUITE_P(Bundled, SolverAgreement, ::testing::ValuesIn(bundledScenarios()), testName);

}  // namespace
}  // namespace packsim
