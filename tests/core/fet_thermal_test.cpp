// A FET on a thermal node: its conduction loss I²·Rds_on heats the node, as a
// first-order RC against ambient, and the energy bookkeeping keeps it on the load side.
// Reference system E: 36 A for 5 minutes took the discharge FETs from ~27 C to ~78 C.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "core/scenario/load_scenario.hpp"
#include "core/sim/plant.hpp"
#include "core/sim/simulation.hpp"
#include "test_support.hpp"

namespace packsim {
namespace {

// The bundled scooter at 27 C, 36 A constant for 300 s; FET node temperature at the end.
double fetTempAfter36A(Scenario s, double* analytic_C) {
  s.ambient_C = TimeSeries::constant(27.0);
  s.pack.initial_temp_C = 27.0;
  s.load = test::scenarioFromYaml(test::simpleCellYaml() + "load: {current_A: 36}\nrun: {duration_s: 300}\n").load;
  s.run.duration_s = 300.0;
  const Plant plant(s);
  const int node = plant.fetNode();
  EXPECT_GE(node, 0);
  double last_C = 0.0;
  runScenario(s, [&](double, const double*, const PlantSignals& sig, const bms::Outputs&) {
    last_C = sig.node_temp_C[static_cast<size_t>(node)];
    return false;
  });
  // The node alone: C dT/dt = I² R - G (T - T_amb), from T_amb; the FET turns on after
  // the BMS's start-up (a few ticks), which this ignores.
  const ThermalNodeConfig& n = s.thermal.nodes.front();
  const double p_W = 36.0 * 36.0 * s.hardware.discharge_fet.rds_on_ohm;
  const double g = n.g_ambient_W_per_K, c = n.heat_capacity_J_per_K;
  *analytic_C = 27.0 + p_W / g * (1.0 - std::exp(-300.0 * g / c));
  return last_C;
}

TEST(FetThermal, ThirtySixAmpsForFiveMinutesTakeTheScooterFetsFrom27To78C) {
  const Scenario s = loadScenarioFile(test::scenarioDir() + "/scooter_16s_lto.yaml");
  double analytic_C = 0.0;
  const double t_C = fetTempAfter36A(s, &analytic_C);
  EXPECT_NEAR(t_C, 78.0, 2.0);          // the team's figure
  EXPECT_NEAR(t_C, analytic_C, 0.5);    // the first-order solution (start-up ticks aside)
}

TEST(FetThermal, TheFetLossIsLoadSideSoTheCellHeatAndEnergyOutAreUnchanged) {
  // The FET loss is dissipated between the pack terminals and the load: it is part of
  // the energy delivered at the terminals, never of the cells' heat. With and without
  // the FET node, the cells see the same current, so the heat and energy quadratures agree.
  Scenario with = loadScenarioFile(test::scenarioDir() + "/scooter_16s_lto.yaml");
  with.load = test::scenarioFromYaml(test::simpleCellYaml() + "load: {current_A: 30}\nrun: {duration_s: 120}\n").load;
  with.run.duration_s = 120.0;
  Scenario without = with;
  without.hardware.discharge_fet.thermal_node.clear();
  const RunResult a = runScenario(with), b = runScenario(without);
  ASSERT_GT(a.quad[kQuadHeat_J], 0.0);
  EXPECT_NEAR(a.quad[kQuadHeat_J], b.quad[kQuadHeat_J], 1e-6 * b.quad[kQuadHeat_J]);
  EXPECT_NEAR(a.quad[kQuadLoadEnergy_J], b.quad[kQuadLoadEnergy_J], 1e-6 * b.quad[kQuadLoadEnergy_J]);
  EXPECT_NEAR(a.quad[kQuadChemEnergy_J], b.quad[kQuadChemEnergy_J], 1e-6 * b.quad[kQuadChemEnergy_J]);
}

// Separate one-way paths (hardware.fet_paths: separate): a charge flows through the
// charge FET alone, so the discharge FETs' node stays at ambient and the loss is the
// charge FET's I² Rds_on; in series the discharge FET, held off while charging, would
// pass the charge through its body diode (Vf + I R) and heat its node.
TEST(FetThermal, OnSeparatePathsAChargeHeatsOnlyTheChargeFet) {
  Scenario s = loadScenarioFile(test::scenarioDir() + "/scooter_16s_lto_charge.yaml");
  s.run.duration_s = 600.0;
  s.expect = Expectations{};
  ASSERT_EQ(s.hardware.fet_paths, FetPaths::Separate);
  const Plant plant(s);
  const size_t node = static_cast<size_t>(plant.fetNode());
  double maxNode_C = -100.0;
  const RunResult r = runScenario(s, [&](double, const double*, const PlantSignals& sig, const bms::Outputs&) {
    maxNode_C = std::max(maxNode_C, sig.node_temp_C[node]);
    return false;
  });
  const Recording& rec = r.rec;
  bool charged = false;
  for (size_t i = 0; i < rec.samples(); ++i) {
    const double i_A = -rec.pack_current_A[i];
    if (i_A < 9.0) continue;
    charged = true;
    EXPECT_NEAR(rec.hw_fet_loss_W[i], i_A * i_A * s.hardware.charge_fet.rds_on_ohm, 1e-9);
  }
  EXPECT_TRUE(charged);
  EXPECT_NEAR(maxNode_C, 20.0, 1e-6);  // the ambient: no discharge current, no heat

  s.hardware.fet_paths = FetPaths::Series;  // the same charge through back-to-back FETs
  double seriesNode_C = -100.0;
  runScenario(s, [&](double, const double*, const PlantSignals& sig, const bms::Outputs&) {
    seriesNode_C = std::max(seriesNode_C, sig.node_temp_C[node]);
    return false;
  });
  EXPECT_GT(seriesNode_C, 40.0);  // ~4 W of body-diode loss into 11 J/K for minutes
}

TEST(FetThermal, OnSeparatePathsTheLoadCannotPushCurrentIntoThePack) {
  std::string y = test::simpleCellYaml() + "load: {current_A: -1}\nrun: {duration_s: 10}\n";
  const std::string hw = "hardware:\n";
  y.insert(y.find(hw) + hw.size(), "  charge_fet: {rds_on_ohm: 0.002}\n  fet_paths: separate\n");
  std::string e = test::yamlErrorOf(y);
  EXPECT_NE(e.find("one-way discharge path"), std::string::npos) << e;
  y.replace(y.find("fet_paths: separate"), 19, "fet_paths: parallel");
  e = test::yamlErrorOf(y);
  EXPECT_NE(e.find("fet_paths"), std::string::npos) << e;
  EXPECT_NE(e.find("separate"), std::string::npos) << e;
}

TEST(FetThermal, AThermalNodeThatDoesNotExistIsAnErrorWithTheClosestName) {
  std::string y = test::simpleCellYaml() + "thermal: {nodes: [{name: fets, heat_capacity_J_per_K: 10}]}\n" +
                  test::kSimpleLoadYaml;
  const std::string hw = "hardware:\n";
  y.insert(y.find(hw) + hw.size(), "  discharge_fet: {thermal_node: fest}\n");
  const std::string e = test::yamlErrorOf(y);
  EXPECT_NE(e.find("thermal_node"), std::string::npos) << e;
  EXPECT_NE(e.find("did you mean 'fets'"), std::string::npos) << e;
}

}  // namespace
}  // namespace packsim
