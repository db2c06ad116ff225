// Active balancing (reference system B checks) on the bundled 4s3p proof-of-concept.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "core/scenario/load_scenario.hpp"
#include "core/scenario/overrides.hpp"

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
  // Two converters in a row, each at best its loss model's efficiency at full current
  // from the highest module voltage (0.861 at 3 A, 4.2 V).
  const ActiveBalancerConfig& a = s.hardware.active_balancer;
  const double best = a.efficiencyAt(a.converter_current_A, a.module_max_V);
  EXPECT_NEAR(best, 1.0 - (0.4 + 0.15 * 9.0) / (4.2 * 3.0), 1e-12);
  EXPECT_LT(eta, best * best) << "cannot beat two converters in a row";
  // The 2.5 F / 5.5 V part never above its rating.
  for (size_t i = 0; i < rec.samples(); ++i) EXPECT_LE(rec.balancer_bus_V[i], a.bus_rated_V);
}

// The supercap's precharge from the whole stack, at its worst (bus empty, every cell
// full): the inrush V_stack / (R_pre + R_stack) stays within the team's 10 A, for the
// 4s3p proof of concept and the 28s15p car.
TEST(ActiveBalancer, PrechargeInrushStaysWithinTenAmps) {
  for (const char* file : {"/balance/solar_4s3p_active.yaml", "/solar_car_28s15p_balancer.yaml"}) {
    const Scenario s =
        loadScenarioFileWithOverrides(test::scenarioDir() + file, {{"pack.initial_soc", "1.0"}, {"pack.cells", "[]"}});
    const Plant plant(s);
    std::vector<double> x(static_cast<size_t>(plant.stateSize()), 0.0), dx(x.size(), 0.0);
    plant.initialState(x.data());
    PlantInputs in;
    in.relay_closed = true;
    in.bus_precharge = true;
    PlantSignals sig = plant.makeSignals();
    in.bus_precharge = false;
    plant.derivatives(0.0, x.data(), in, dx.data(), sig);
    const double stack_V = sig.pack_voltage_V, R = s.hardware.active_balancer.precharge_ohm;
    EXPECT_GT(stack_V, s.pack.series * 4.15) << file;
    in.bus_precharge = true;
    plant.derivatives(0.0, x.data(), in, dx.data(), sig);
    EXPECT_NEAR(sig.bus_V, 0.0, 1e-12) << file;
    EXPECT_LT(sig.bus_current_A, stack_V / R) << file;          // less the drop in the stack's own R
    EXPECT_GT(sig.bus_current_A, 0.95 * stack_V / R) << file;   // which is small against R_pre
    EXPECT_LE(sig.bus_current_A, 10.0) << file;
  }
}

// The race preset with the balancer beside the one without (the reason the team built
// it): the balancer carries charge from the strong modules to the weak ones while they
// race, so the weakest module ends the race later and the pack delivers more. Checks:
// the energy stranded by imbalance falls to less than half, at least half of what was
// stranded comes out as energy delivered, the chain (module -> bus -> module) keeps more
// than half of what it moves and cannot beat two converters at their best, and from the
// trip on every converter is off.
TEST(ActiveBalancer, SystemBRaceWithTheBalancerRecoversStrandedEnergy) {
  Scenario with = loadScenarioFile(test::scenarioDir() + "/solar_car_28s15p_balancer.yaml");
  with.compare_scenario.clear();  // its `compare:` is the race without it: run once, below
  const RunResult b = runScenario(with);
  const RunResult a = runScenario(loadScenarioFile(test::scenarioDir() + "/solar_car_28s15p.yaml"));
  ASSERT_TRUE(a.summary.tripped && b.summary.tripped);
  EXPECT_EQ(b.summary.trip_reason, "cell_undervoltage");
  EXPECT_GT(b.summary.trip_time_s, a.summary.trip_time_s);
  EXPECT_LT(b.summary.energy_stranded_Wh, 0.5 * a.summary.energy_stranded_Wh);
  EXPECT_GT(b.summary.energy_delivered_Wh - a.summary.energy_delivered_Wh, 0.5 * a.summary.energy_stranded_Wh);
  const ActiveBalancerConfig& ab = with.hardware.active_balancer;
  const double from = b.quad[kQuadConverterFromModules_J], to = b.quad[kQuadConverterToModules_J];
  const double best = ab.efficiencyAt(ab.converter_current_A, ab.module_max_V);
  ASSERT_GT(from, 0.0);
  EXPECT_GT(to / from, 0.5) << "chain efficiency over the race";
  EXPECT_LT(to / from, best * best);
  // Isolated: converters off from the trip on.
  EXPECT_GE(test::eventTime(b, "active_balancer", "safe state: the BMS isolated the pack, converters off"),
            b.summary.trip_time_s - 1e-9);
  for (size_t i = 0; i < b.rec.samples(); ++i) {
    if (b.rec.time_s[i] <= b.summary.trip_time_s + with.bms.tick_s) continue;
    for (int g = 0; g < with.pack.series; ++g)
      EXPECT_EQ(b.rec.balance_current_A[i * static_cast<size_t>(with.pack.series) + static_cast<size_t>(g)], 0.0);
  }
}

TEST(ActiveBalancer, EfficiencyEitherFromATableOrFromALossModel) {
  auto withBalancer = [](const std::string& ab) {
    std::string y = test::simpleCellYaml() + test::kSimpleLoadYaml;
    y.insert(y.find("hardware:\n") + 10, "  active_balancer: " + ab + "\n");
    return y;
  };
  const std::string both =
      test::yamlErrorOf(withBalancer("{efficiency: 0.8, losses: {fixed_W: 0.4, series_ohm: 0.15}}"));
  EXPECT_NE(both.find("either efficiency or losses"), std::string::npos) << both;
  const std::string typo = test::yamlErrorOf(withBalancer("{losses: {fixed_w: 0.4}}"));
  EXPECT_NE(typo.find("fixed_W"), std::string::npos) << typo;
  ActiveBalancerConfig c;
  c.loss_model = true, c.loss_fixed_W = 0.4, c.loss_series_ohm = 0.15;
  EXPECT_NEAR(c.efficiencyAt(0.5, 3.7), 1.0 - (0.4 + 0.15 * 0.25) / 1.85, 1e-12);
  EXPECT_NEAR(c.efficiencyAt(1e-6, 3.7), 0.01, 1e-12);  // the fixed loss exceeds the power: floor
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
