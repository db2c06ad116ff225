// RunTracker::checkFinite (core/sim/run_tracker.hpp): a state with an infinite or NaN
// element stops the run with an error naming the first such element; a finite one, at
// the ends of the double range and with signed zeros, passes. (It sums x·0 over the
// state first and looks element by element only when that sum is not 0.)
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/sim/bms_image.hpp"
#include "core/sim/plant.hpp"
#include "core/sim/run_tracker.hpp"
#include "core/sim/soc_error.hpp"
#include "test_support.hpp"

namespace packsim {
namespace {

TEST(RunTracker, CheckFiniteNamesTheFirstNonFiniteStateAndPassesEveryFiniteOne) {
  const Scenario s = test::scenarioFromYaml(test::simpleCellYaml(2) + "load: {current_A: 1}\nrun: {duration_s: 10}\n");
  const Plant plant(s);
  const bms::Config cfg = makeBmsConfig(s);
  RunTracker tracker(s, plant, cfg);
  constexpr double kInf = std::numeric_limits<double>::infinity();
  const double kMax = std::numeric_limits<double>::max(), kMin = std::numeric_limits<double>::denorm_min();
  const std::vector<double> finite = {0.0, -0.0, kMax, -kMax, kMin, -kMin, 3.7, -1e-300, 2.0};  // an odd count
  EXPECT_NO_THROW(tracker.checkFinite(1.0, finite.data(), static_cast<int>(finite.size())));
  for (const double bad : {kInf, -kInf, std::nan("")}) {
    for (int at : {0, 3, 7, 8}) {
      std::vector<double> x = finite;
      x[static_cast<size_t>(at)] = bad;
      if (at == 3) x[7] = bad;  // two: the first is named
      try {
        tracker.checkFinite(2.5, x.data(), static_cast<int>(x.size()));
        ADD_FAILURE() << "no error for " << bad << " at " << at;
      } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("diverged at t = 2.5 s (state " + std::to_string(at) + " is not finite)"),
                  std::string::npos)
            << e.what();
      }
    }
  }
}

// The quick pass sums the state: huge finite values whose sum overflows still pass (the
// one-by-one look finds them finite), and a value that is not finite is named wherever it
// stands (the rounds of four, the pair after them, the odd last one), in states of
// every length up to 21.
TEST(RunTracker, CheckFiniteLooksPastAnOverflowingSumAndFindsEveryPosition) {
  const Scenario s = test::scenarioFromYaml(test::simpleCellYaml(2) + "load: {current_A: 1}\nrun: {duration_s: 10}\n");
  const Plant plant(s);
  const bms::Config cfg = makeBmsConfig(s);
  RunTracker tracker(s, plant, cfg);
  const double kMax = std::numeric_limits<double>::max();
  const std::vector<double> huge(21, kMax);
  EXPECT_NO_THROW(tracker.checkFinite(1.0, huge.data(), static_cast<int>(huge.size())));
  for (int n = 1; n <= 21; ++n) {
    const std::vector<double> fine(static_cast<size_t>(n), 1.5);
    EXPECT_NO_THROW(tracker.checkFinite(1.0, fine.data(), n));
    for (int at = 0; at < n; ++at) {
      std::vector<double> x = fine;
      x[static_cast<size_t>(at)] = at % 2 ? std::nan("") : -std::numeric_limits<double>::infinity();
      try {
        tracker.checkFinite(3.0, x.data(), n);
        ADD_FAILURE() << "no error at " << at << " of " << n;
      } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("(state " + std::to_string(at) + " is not finite)"), std::string::npos)
            << e.what();
      }
    }
  }
}

// SocErrorTracker keeps its max by a compare instead of std::fmax: the same bits as
// fmax over errors of every kind (signed zeros, NaN estimates, huge and tiny ones).
// RunTracker::tick's summary extremes (run_tracker.cpp) follow from each tick's lowest
// voltage and highest temperature: the same cells, values and times as the plain scan of
// the cells in order with strict comparisons, ties included (each tick's values drawn
// from two levels that step down, or up, every 20 ticks: several cells reach a new
// extreme in the same tick), and the same first cell at or below its v_min.
TEST(RunTracker, SummaryExtremesMatchTheInOrderScan) {
  constexpr int kCells = 4;
  const Scenario s = test::scenarioFromYaml(test::simpleCellYaml(kCells) + test::kSimpleLoadYaml);
  const Plant plant(s);
  const bms::Config cfg = makeBmsConfig(s);
  RunTracker tracker(s, plant, cfg);
  PlantSignals sig = plant.makeSignals();
  std::vector<double> x(static_cast<size_t>(plant.stateSize() + kQuadCount), 0.0);
  plant.initialState(x.data());
  const bms::Outputs out{};
  const double vMin = plant.pack().cells[0].v_min_V;
  double minV = INFINITY, minV_s = 0.0, maxT = -INFINITY, maxT_s = 0.0, limit_s = 0.0;
  int minCell = 0, hottest = 0, limitCell = 0;
  uint32_t draw = 7;
  for (int k = 0; k < 300; ++k) {
    const double t = 0.01 * k;
    for (int c = 0; c < kCells; ++c) {
      draw = draw * 1664525u + 1013904223u;
      const double step = static_cast<double>(k / 20);
      const double v = vMin + 0.3 - 0.05 * step + ((draw >> 16) & 1 ? 0.05 : 0.0);
      const double T = 24.0 + 0.5 * step - ((draw >> 8) & 1 ? 0.5 : 0.0);
      sig.cell_voltage_V[static_cast<size_t>(c)] = v;
      x[static_cast<size_t>(plant.tempIndex(c))] = T;
      if (v < minV) minV = v, minCell = c + 1, minV_s = t;
      if (T > maxT) maxT = T, hottest = c + 1, maxT_s = t;
      if (limitCell == 0 && v <= plant.pack().cells[static_cast<size_t>(c)].v_min_V) limitCell = c + 1, limit_s = t;
    }
    tracker.tick(t, x.data(), sig, out);
  }
  ASSERT_NE(limitCell, 0);
  const RunResult r = tracker.finish(x.data() + plant.stateSize(), "test");
  const Summary& sm = r.summary;
  EXPECT_EQ(sm.min_cell_V, minV);
  EXPECT_EQ(sm.min_cell, minCell);
  EXPECT_EQ(sm.min_cell_time_s, minV_s);
  EXPECT_EQ(sm.max_temp_C, maxT);
  EXPECT_EQ(sm.hottest_cell, hottest);
  EXPECT_EQ(sm.hottest_time_s, maxT_s);
  EXPECT_TRUE(sm.limit_reached);
  EXPECT_EQ(sm.limit_cell, limitCell);
  EXPECT_EQ(sm.limit_time_s, limit_s);
}

TEST(SocErrorTracker, MaxIsFmaxOfTheAbsoluteErrors) {
  const double nan = std::nan(""), inf = std::numeric_limits<double>::infinity();
  const std::vector<double> estimates = {0.5, -0.0, 0.0, nan, 0.25, 1e-310, -1e300, 0.75, nan, 0.5, inf, 0.1};
  for (const double truth : {0.0, -0.0, 0.5, 0.3, nan}) {
    SocErrorTracker tracker;
    double expected = 0.0;
    for (const double e : estimates) {
      tracker.add(e, truth);
      expected = std::fmax(expected, std::fabs(e - truth));
      const double got = tracker.stats().max;
      EXPECT_EQ(std::memcmp(&got, &expected, sizeof got), 0) << e << " against " << truth;
    }
  }
}

}  // namespace
}  // namespace packsim
