// RunTracker::checkFinite (core/sim/run_tracker.hpp): a state with an infinite or NaN
// element stops the run with an error naming the first such element; a finite one, at
// the ends of the double range and with signed zeros, passes. (It sums x·0 over the
// state first and looks element by element only when that sum is not 0.)
#include <gtest/gtest.h>

#include <cmath>
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
