// Exact breakpoints (core/sim/simulation.cpp step 5, core/sim/same_instant.hpp): both
// integrators stop at every input discontinuity wherever it falls relative to the tick --
// a load step, a logger's rows, a scripted fault starting or ending -- and never fail
// because rounding put a breakpoint a few ulps from a tick (70 · 0.01 != 0.7: CVODE
// refused that sliver with flag -27 for 17 of the step times 0.1 … 10.0 s).
//
// The oracle needs no stored output: with no balancing, the charge out of the pack is
// the load's integral from the instant the relay contact closed, which a step or linear profile gives
// in closed form (LoadProfile::chargeUntil_As); a breakpoint taken at the wrong instant
// shifts it by (step) × (offset), up to 3 A × 10 ms here -- 300x the tolerance.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <random>

#include "core/sim/simulation.hpp"
#include "test_support.hpp"

namespace packsim {
namespace {

constexpr double kTolAs = 1e-4;  // charge: CVODE's quadrature at rtol, far below 3 A · 10 ms

// Two cells at a 10 ms tick, run for duration_s on `solver`; the load is appended.
std::string twoCellPack(const std::string& solver, double duration_s) {
  return test::simpleCellYaml(2) + "bms: {tick_ms: 10}\nrun: {solver: " + solver +
         ", duration_s: " + std::to_string(duration_s) + "}\n";
}

struct Outcome {
  double charge_As = 0.0;
  double minCell_V = 0.0;
};

// Runs s; the charge it delivered against the load's integral from the contact closing,
// to tol_As.
Outcome runIt(const Scenario& s, double tol_As = kTolAs) {
  const RunResult r = runScenario(s);
  EXPECT_FALSE(r.summary.tripped) << s.name;
  EXPECT_NEAR(r.summary.duration_s, s.run.duration_s, 1e-9);
  const double closed_s = test::eventTime(r, "relay_contact", "closed");
  EXPECT_GE(closed_s, 0.0);
  const double charge_As = 3600.0 * r.summary.charge_delivered_Ah;
  EXPECT_NEAR(charge_As, s.load.chargeUntil_As(s.run.duration_s) - s.load.chargeUntil_As(closed_s), tol_As);
  return {charge_As, r.summary.min_cell_V};
}

// A 4 A step down to 1 A at 0.1, 0.2 … 10.0 s, written as a user writes them ("0.7",
// which is not 70 ticks of 0.01 s in binary), and between ticks (+0.0037 s), both
// integrators: each run completes, its charge is the load's integral,
// and the two integrators agree.
TEST(Breakpoints, LoadStepsAnywhereInTheTickRunWithBothSolvers) {
  for (int i = 1; i <= 100; ++i) {
    for (const double extra : {0.0, 0.0037}) {
      const double ts = 0.1 * i + extra;
      char load[160];
      std::snprintf(load, sizeof load,
                    "load: {segments: [{duration_s: %.4f, current_A: 4}, {duration_s: 30, current_A: 1}]}\n", ts);
      Outcome o[2];
      int j = 0;
      for (const char* solver : {"cvode", "fast"}) {
        const Scenario s = test::scenarioFromYaml(twoCellPack(solver, 10.5) + load);
        SCOPED_TRACE(std::string(solver) + " step at " + std::to_string(ts));
        o[j] = runIt(s);
        ++j;
      }
      EXPECT_NEAR(o[0].charge_As, o[1].charge_As, kTolAs) << "step at " << ts;
      EXPECT_NEAR(o[0].minCell_V, o[1].minCell_V, 1e-3) << "step at " << ts;
    }
  }
}

// A data logger's CSV at 10 Hz and at 100 Hz (times written as decimals, none a multiple
// of the tick in binary), step and linear: the run completes with both integrators and
// delivers the profile's integral. On a linear piece CVODE's charge quadrature is only
// error-controlled (absolute tolerance 1e-3 As a step, and every breakpoint restarts it
// at first order): 0.01 As over the 2,000 pieces; the step pieces stay exact.
TEST(Breakpoints, LoggerCsvsAt10And100HzRunWithBothSolvers) {
  const std::filesystem::path dir = test::processTempDir("breakpoint_csv");
  std::mt19937 gen(7);
  std::uniform_real_distribution<double> amps(-1.0, 5.0);
  for (const int hz : {10, 100}) {
    const std::filesystem::path csv = dir / ("log_" + std::to_string(hz) + "hz.csv");
    {
      std::ofstream f(csv);
      f << "time_s,current_A\n";
      for (int i = 0; i <= 20 * hz; ++i) f << (static_cast<double>(i) / hz) << "," << amps(gen) << "\n";
    }
    for (const char* interp : {"step", "linear"}) {
      for (const char* solver : {"cvode", "fast"}) {
        SCOPED_TRACE(std::to_string(hz) + " Hz, " + interp + ", " + solver);
        const Scenario s = test::scenarioFromYaml(twoCellPack(solver, 19.95) + "load: {csv: " + csv.string() +
                                                  ", interpolation: " + interp + "}\n");
        runIt(s, std::string(interp) == "linear" && std::string(solver) == "cvode" ? 0.01 : kTolAs);
      }
    }
  }
}

// A scripted fault inside a tick starts and ends at its own instants (events at
// 1.2345 s and 1.7345 s, not at the ticks after them), and its extra load flows for
// exactly its duration.
TEST(Breakpoints, TimedFaultsActAtTheirOwnInstant) {
  for (const char* solver : {"cvode", "fast"}) {
    SCOPED_TRACE(solver);
    const Scenario s = test::scenarioFromYaml(
        twoCellPack(solver, 3.0) +
        "load: {current_A: 1}\n"
        "faults:\n  - {kind: overcurrent, current_A: 2, at_s: 1.2345, duration_s: 0.5}\n");
    const RunResult r = runScenario(s);
    EXPECT_DOUBLE_EQ(test::eventTime(r, "fault_injected"), 1.2345);
    EXPECT_NEAR(test::eventTime(r, "fault_removed"), 1.7345, 1e-12);
    const double closed_s = test::eventTime(r, "relay_contact", "closed");
    EXPECT_NEAR(3600.0 * r.summary.charge_delivered_Ah, 1.0 * (3.0 - closed_s) + 2.0 * 0.5, kTolAs);
  }
}

}  // namespace
}  // namespace packsim
