// A thermistor on the power FETs' thermal node (reference system E: the AFE's TS3 on the
// discharge FETs, a fourth thermistor on the MCU's own ADC). The FET channel is judged by
// its own limit, fet_overtemperature, never as a cell temperature; the AFE's FET
// over-temperature (OTF) is the backstop behind the firmware. Expectations come from the
// node's first-order solution, T(t) = T_amb + P/G · (1 − exp(−G t / C)).
#include <gtest/gtest.h>

#include <cmath>

#include "core/scenario/load_scenario.hpp"
#include "core/sim/plant.hpp"
#include "core/sim/simulation.hpp"
#include "test_support.hpp"

namespace packsim {
namespace {

using F = bms::FaultId;

Scenario fetOverheat() { return loadScenarioFile(test::scenarioDir() + "/faults/e_fet_overheat.yaml"); }

// When the FET node, heated by I² Rds_on from the ambient, reaches limit_C.
double analyticTimeTo(const Scenario& s, double current_A, double limit_C) {
  const ThermalNodeConfig& n = s.thermal.nodes.front();
  const double p_W = current_A * current_A * s.hardware.discharge_fet.rds_on_ohm;
  const double rise_K = p_W / n.g_ambient_W_per_K, ambient_C = s.pack.initial_temp_C;
  return -n.heat_capacity_J_per_K / n.g_ambient_W_per_K * std::log(1.0 - (limit_C - ambient_C) / rise_K);
}

TEST(FetThermistor, TheFetLimitTripsAtTheNodesFirstOrderTimeAndTheCellRuleNever) {
  const Scenario s = fetOverheat();
  const double t85 = analyticTimeTo(s, 40.0, 85.0), t55 = analyticTimeTo(s, 40.0, 55.0);
  EXPECT_NEAR(t85, 268.0, 1.0);  // the scenario's comment
  const RunResult r = runScenario(s);
  const Recording& rec = r.rec;
  ASSERT_TRUE(r.summary.tripped);
  EXPECT_EQ(r.summary.trip_reason, "fet_overtemperature");
  // 2 s debounce after a read-out that sees 85 C: the measurements come every 5 s.
  EXPECT_GE(r.summary.trip_time_s, t85 + 2.0 - 0.05);
  EXPECT_LE(r.summary.trip_time_s, t85 + 2.0 + 5.0 + 0.05);
  // The FET channel was above the cells' 55 C limit for over a minute before: had it
  // counted as a cell temperature, overtemperature would have tripped first.
  ASSERT_LT(t55 + 60.0, t85);
  for (uint32_t bits : rec.fault_active) EXPECT_EQ(bits & bms::faultBit(F::OverTemperature), 0u);
  EXPECT_LT(r.summary.max_temp_C, 35.0);
  // Both FETs open: no current after the trip (the BMS's own decision and the hardware).
  const size_t last = rec.samples() - 1;
  EXPECT_EQ(rec.hw_discharge_fet_on[last], 0);
  EXPECT_NEAR(rec.pack_current_A[last], 0.0, 1e-9);
}

TEST(FetThermistor, TheAfesOwnFetLimitOpensTheFetsWhenTheFirmwareDoesNot) {
  Scenario s = fetOverheat();
  s.bms.protection(F::FetOverTemperature).enabled = false;
  s.expect = Expectations{};
  const double t95 = analyticTimeTo(s, 40.0, 95.0);  // the preset's OTF
  const RunResult r = runScenario(s);
  const Recording& rec = r.rec;
  double opened_s = -1.0;
  for (size_t i = 0; i < rec.samples() && opened_s < 0.0; ++i)
    if (rec.time_s[i] > 10.0 && rec.hw_discharge_fet_on[i] == 0) opened_s = rec.time_s[i];
  // OTF's 2 s delay on the part's 60 ms measurement loop, seen at 1 s recording steps.
  EXPECT_GE(opened_s, t95 + 2.0 - 0.1);
  EXPECT_LE(opened_s, t95 + 2.0 + 1.1);
}

TEST(FetThermistor, EachChannelReadsItsSiteTheFetsOnTheAfeAndTheFourthOnTheMcu) {
  const Scenario s = fetOverheat();
  ASSERT_EQ(s.hardware.thermistor_sites.size(), 4u);
  EXPECT_EQ(s.hardware.afe.fet_inputs, 1u << 2);  // TS3
  const Plant plant(s);
  const size_t fetNode = static_cast<size_t>(plant.fetNode());
  std::vector<double> fet_C;
  const RunResult r = runScenario(s, [&](double, const double*, const PlantSignals& sig, const bms::Outputs&) {
    fet_C.push_back(sig.node_temp_C[fetNode]);
    return false;
  });
  const Recording& rec = r.rec;
  ASSERT_EQ(rec.thermistors, 4);
  // Compare where the 5 s read-out is fresh and the temperatures move slowly: every
  // channel within 1.5 C of its site at the same instant 5 s earlier at most.
  const double dt = s.bms.tick_s;
  for (size_t i = 10; i + 1 < rec.samples(); i += 10) {
    const double t = rec.time_s[i];
    const size_t tick = static_cast<size_t>(std::lround(t / dt));
    ASSERT_LT(tick, fet_C.size());
    const size_t before = tick >= 500 ? tick - 500 : 0;
    const int16_t* m = &rec.meas_temperature_dC[i * 4];
    EXPECT_NEAR(m[0] * 0.1, rec.cell_temp_C[i * 16 + 0], 1.5) << "t " << t;
    EXPECT_NEAR(m[1] * 0.1, rec.cell_temp_C[i * 16 + 7], 1.5) << "t " << t;
    EXPECT_NEAR(m[3] * 0.1, rec.cell_temp_C[i * 16 + 15], 1.5) << "t " << t;  // the MCU's ADC
    EXPECT_GE(m[2] * 0.1, fet_C[before] - 1.0) << "t " << t;
    EXPECT_LE(m[2] * 0.1, fet_C[tick] + 1.0) << "t " << t;
  }
}

TEST(FetThermistor, AThermistorOnANodeThatIsNoFetsNodeOrBothFormsAreErrors) {
  std::string base = test::simpleCellYaml() + "thermal: {nodes: [{name: fets, heat_capacity_J_per_K: 10}, "
                                              "{name: busbar, heat_capacity_J_per_K: 10}]}\n" +
                     test::kSimpleLoadYaml;
  const std::string hw = "hardware:\n", at = "  thermistors: {at_groups: [1]}\n";
  auto withHardware = [&](const std::string& lines) {
    std::string y = base;
    y.replace(y.find(at), at.size(), lines);
    return y;
  };
  const std::string fet = "  discharge_fet: {thermal_node: fets}\n";
  std::string e = test::yamlErrorOf(withHardware(fet + "  thermistors: {channels: [{group: 1}, {node: busbar}]}\n"));
  EXPECT_NE(e.find("channels[1].node"), std::string::npos) << e;
  EXPECT_NE(e.find("FETs' node"), std::string::npos) << e;
  e = test::yamlErrorOf(withHardware(fet + "  thermistors: {channels: [{group: 1}, {node: fest}]}\n"));
  EXPECT_NE(e.find("did you mean 'fets'"), std::string::npos) << e;
  e = test::yamlErrorOf(withHardware(fet + "  thermistors: {at_groups: [1], channels: [{group: 1}]}\n"));
  EXPECT_NE(e.find("not both"), std::string::npos) << e;
  e = test::yamlErrorOf(withHardware(fet + "  thermistors: {channels: [{group: 1, node: fets}]}\n"));
  EXPECT_NE(e.find("either {group: N} or {node: NAME}"), std::string::npos) << e;
  e = test::yamlErrorOf(withHardware(fet + "  thermistors: {channels: [{group: 2}]}\n"));
  EXPECT_NE(e.find("group"), std::string::npos) << e;
  // Accepted: a FET channel on the FETs' node.
  const Scenario ok = test::scenarioFromYaml(withHardware(fet + "  thermistors: {channels: [{group: 1}, {node: fets}]}\n"));
  ASSERT_EQ(ok.hardware.thermistor_sites.size(), 2u);
  EXPECT_EQ(ok.hardware.thermistor_sites[1].node, "fets");
}

}  // namespace
}  // namespace packsim
