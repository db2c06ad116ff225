// Active balancing (reference system B checks) on the bundled 4s3p proof-of-concept.
#include <gtest/gtest.h>

#include <cmath>

#include "core/sim/plant.hpp"
#include "core/sim/simulation.hpp"
#include "test_support.hpp"

namespace packsim {
namespace {

TEST(ActiveBalancer, SystemBChecksOverThirtyMinutes) {
  const Scenario s = loadScenarioFile(test::scenarioDir() + "/balance/solar_4s3p_active.yaml");
  const RunResult r = runScenario(s);
  const Recording& rec = r.rec;
  const int series = s.pack.series, parallel = s.pack.parallel;
  ASSERT_NEAR(rec.time_s.back(), 1800.0, 1e-9);
  // Rest voltage (OCV) of each module from its cells' SOC: free of the converters' I·R.
  auto moduleOcv = [&](size_t sample, int g) {
    double v = 0.0;
    for (int k = 0; k < parallel; ++k)
      v += ecm::ocv(s.pack.cell, rec.cell_soc[sample * static_cast<size_t>(rec.cells) + static_cast<size_t>(g * parallel + k)]);
    return v / parallel;
  };
  const size_t last = rec.samples() - 1;
  double avg0 = 0.0;
  for (int g = 0; g < series; ++g) avg0 += moduleOcv(0, g) / series;
  int farModules = 0;
  for (int g = 0; g < series; ++g) {
    const double v0 = moduleOcv(0, g), v1 = moduleOcv(last, g);
    if (std::fabs(v0 - avg0) <= 0.2) continue;
    ++farModules;
    const double towards = (v0 > avg0) ? v0 - v1 : v1 - v0;
    EXPECT_GE(towards, 0.1) << "module " << g + 1 << " from " << v0 << " V (average " << avg0 << " V)";
  }
  EXPECT_EQ(farModules, 2) << "the scenario starts two modules more than 0.2 V out";
  // No module leaves 2.5-4.2 V (terminal voltage, every sample).
  for (size_t i = 0; i < rec.samples(); ++i)
    for (int g = 0; g < series; ++g) {
      const double v = rec.cell_voltage_V[i * static_cast<size_t>(rec.cells) + static_cast<size_t>(g * parallel)];
      EXPECT_GT(v, 2.5);
      EXPECT_LT(v, 4.2);
    }
  // Chain efficiency: energy into the low modules per energy out of the high ones, net
  // of what the bus kept after its precharge (first sample with a converter running).
  size_t start = 0;
  while (start < rec.samples()) {
    bool any = false;
    for (int g = 0; g < series; ++g) any = any || rec.balance_current_A[start * series + static_cast<size_t>(g)] != 0.0;
    if (any) break;
    ++start;
  }
  ASSERT_LT(start, rec.samples());
  const double C = s.hardware.active_balancer.bus_capacitance_F;
  const double kept_J = 0.5 * C * (std::pow(rec.balancer_bus_V[last], 2) - std::pow(rec.balancer_bus_V[start], 2));
  const double from = r.quad[kQuadConverterFromModules_J], to = r.quad[kQuadConverterToModules_J];
  ASSERT_GT(from, 0.0);
  const double eta = to / (from - kept_J);
  EXPECT_GT(eta, 0.5);
  EXPECT_LT(eta, 0.85 * 0.85 + 0.02) << "cannot beat two converters in a row";
}

TEST(ActiveBalancer, SafeStateTurnsEveryConverterOff) {
  ActiveBalancerConfig c;
  c.present = true;
  ActiveBalancerCommand cmd = activeBalancerDecide(c, {3.9, 3.6, 3.3}, 3.0);
  EXPECT_EQ(cmd.source, 0);
  EXPECT_EQ(cmd.sink, 2);
  cmd = activeBalancerDecide(c, {4.25, 3.6, 3.3}, 3.0);
  EXPECT_TRUE(cmd.safe_state);
  EXPECT_EQ(cmd.source, -1);
  EXPECT_EQ(cmd.sink, -1);
  cmd = activeBalancerDecide(c, {3.9, 3.6, 2.45}, 3.0);
  EXPECT_TRUE(cmd.safe_state);
  cmd = activeBalancerDecide(c, {3.9, 3.6, 3.3}, 1.5);  // bus below 2 V: precharge only
  EXPECT_TRUE(cmd.precharge);
  EXPECT_EQ(cmd.source, -1);
  cmd = activeBalancerDecide(c, {3.9, 3.6, 3.3}, 4.6);  // bus full: only feeds the lowest
  EXPECT_EQ(cmd.source, -1);
  EXPECT_EQ(cmd.sink, 2);
}

}  // namespace
}  // namespace packsim
