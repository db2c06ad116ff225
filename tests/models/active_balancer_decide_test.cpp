// The active balancer's decision (models/balance/active_balancer) when the BMS has
// isolated the pack: a unit test in the quick set (the race that reaches it, system B's
// with its balancer, is a `physics` test outside the sanitizer pass).
#include <gtest/gtest.h>

#include "models/balance/active_balancer.hpp"

namespace packsim {
namespace {

// The same modules and bus that move charge from the highest module to the lowest (or
// precharge an empty bus) while the pack is connected: once the BMS isolates the pack,
// every converter and the precharge are off, and the command says why.
TEST(ActiveBalancerDecide, AnIsolatedPackTurnsEveryConverterAndThePrechargeOff) {
  ActiveBalancerConfig c;
  c.present = true;
  const std::vector<double> modules_V = {3.9, 3.6, 3.3};
  const ActiveBalancerCommand connected = activeBalancerDecide(c, modules_V, 3.0, false);
  ASSERT_EQ(connected.source, 0);
  ASSERT_EQ(connected.sink, 2);
  ASSERT_FALSE(connected.safe_state);
  ASSERT_TRUE(activeBalancerDecide(c, modules_V, 1.5, false).precharge);
  for (double bus_V : {1.5, 3.0, 4.6}) {
    const ActiveBalancerCommand cmd = activeBalancerDecide(c, modules_V, bus_V, true);
    EXPECT_TRUE(cmd.safe_state) << bus_V;
    EXPECT_TRUE(cmd.isolated) << bus_V;
    EXPECT_FALSE(cmd.precharge) << bus_V;
    EXPECT_EQ(cmd.source, -1) << bus_V;
    EXPECT_EQ(cmd.sink, -1) << bus_V;
  }
  // A module out of its range is a safe state of its own, not an isolation.
  const ActiveBalancerCommand high = activeBalancerDecide(c, {4.25, 3.6, 3.3}, 3.0, false);
  EXPECT_TRUE(high.safe_state);
  EXPECT_FALSE(high.isolated);
}

}  // namespace
}  // namespace packsim
