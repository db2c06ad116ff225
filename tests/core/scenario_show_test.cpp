// `packsim show`: where each value came from (file:line of the extends chain, preset,
// --set, default, derived default), the runnable YAML form, the warnings table and the
// hardware a user's pack gets when it states none (docs/scenario.md).
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "core/scenario/overrides.hpp"
#include "core/scenario/provenance.hpp"
#include "core/scenario/rest_noise_warning.hpp"
#include "core/scenario/scenario_show.hpp"
#include "core/scenario/scenario_warnings.hpp"
#include "core/sim/simulation.hpp"
#include "core/sim/summary_text.hpp"
#include "models/random/random.hpp"
#include "models/sensors/current_sense.hpp"
#include "test_support.hpp"

namespace packsim {
namespace {

namespace fs = std::filesystem;

void writeFile(const fs::path& p, const std::string& text) {
  std::ofstream out(p);
  out << text;
}

std::string originOf(const Scenario& s, const std::string& key) {
  EXPECT_TRUE(s.provenance);
  return s.provenance ? s.provenance->originOf(key) : "";
}

// Warnings that contain `needle`.
size_t warningsWith(const Scenario& s, const std::string& needle) {
  size_t n = 0;
  for (const std::string& w : s.warnings) n += w.find(needle) != std::string::npos;
  return n;
}

std::string allWarnings(const Scenario& s) {
  std::string all;
  for (const std::string& w : s.warnings) all += w + "\n";
  return all;
}

// A user's pack: 24s4p of the bundled NCR18650 preset, nothing about its hardware.
std::string userPack(const std::string& extra) {
  return "name: user_pack\n"
         "pack: {series: 24, parallel: 4, initial_soc: 0.9, cell: {preset: ncr18650_3p1Ah}}\n" + extra;
}

// test::simpleCellYaml() with more `hardware:` lines, and its 1 A load.
std::string withHardware(const std::string& lines) {
  std::string y = test::simpleCellYaml();
  const std::string ambient = "ambient: {temp_C: 25}\n";
  y.insert(y.find(ambient), lines);
  return y + test::kSimpleLoadYaml;
}

TEST(ScenarioShow, EachValueNamesTheFileLineOfTheChainPresetSetOrDefault) {
  const fs::path dir = test::freshTempDir("packsim_show_", "chain");
  writeFile(dir / "base.yaml",
            "name: base\n"                                             // 1
            "pack:\n"                                                  // 2
            "  series: 4\n"                                            // 3
            "  initial_soc: 0.5\n"                                     // 4
            "  cell: {preset: lipo_5Ah}\n"                             // 5
            "load: {current_A: 2}\n"                                   // 6
            "run: {duration_s: 10}\n");                                // 7
  writeFile(dir / "child.yaml",
            "extends: base.yaml\n"                                     // 1
            "name: child\n"                                            // 2
            "pack:\n"                                                  // 3
            "  initial_soc: 0.8\n");                                   // 4
  const Scenario s = loadScenarioFileWithOverrides((dir / "child.yaml").string(), {{"pack.initial_temp_C", "30"}});
  const std::string base = (dir / "base.yaml").lexically_normal().string();
  const std::string child = (dir / "child.yaml").lexically_normal().string();
  EXPECT_EQ(originOf(s, "pack.series"), base + ":3");
  EXPECT_EQ(originOf(s, "pack.initial_soc"), child + ":4");
  EXPECT_EQ(originOf(s, "name"), child + ":2");
  EXPECT_EQ(originOf(s, "load.current_A"), base + ":6");
  EXPECT_EQ(originOf(s, "pack.initial_temp_C"), "--set pack.initial_temp_C=30");
  EXPECT_EQ(originOf(s, "pack.cell.preset"), base + ":5");
  EXPECT_EQ(originOf(s, "pack.cell.capacity_Ah"), "preset lipo_5Ah (lipo_5Ah.yaml:2)");
  EXPECT_EQ(originOf(s, "pack.parallel"), "default");
  EXPECT_EQ(s.provenance->find("pack.initial_soc")->value, "0.8");
  // Derived: the charge limit from the cell (1C of 5 Ah), the sensor from the limits.
  EXPECT_EQ(originOf(s, "bms.protections.overcurrent_charge.threshold_A"),
            "default (1C x 5 Ah x 1 in parallel: the cell states no max_charge_C)");
  EXPECT_DOUBLE_EQ(s.bms.protection(bms::FaultId::OverCurrentCharge).threshold, 5.0);
  EXPECT_NE(originOf(s, "hardware.current_sense.amp_gain").find("1.5 x the highest over-current limit 30 A"),
            std::string::npos);
  // The text form groups by section and names the origins.
  const std::string text = showText(s);
  EXPECT_NE(text.find("\npack\n"), std::string::npos) << text;
  EXPECT_NE(text.find(base + ":3"), std::string::npos) << text;
}

// The summary without its warning lines (a warning names the file that states its key:
// the shown copy, not the original).
std::string summaryBody(const Scenario& s, const RunResult& r) {
  std::istringstream in(formatSummary(s, r));
  std::string line, out;
  while (std::getline(in, line))
    if (line.rfind("warning", 0) != 0) out += line + "\n";
  return out;
}

// `show --format yaml` runs to the same results as the scenario it shows.
void expectYamlRunsTheSame(const std::string& rel, const Overrides& set) {
  const fs::path path = fs::path(test::scenarioDir()) / rel;
  const Scenario s = loadScenarioFileWithOverrides(path.string(), set);
  const std::string yaml = showYaml(s);
  const Scenario again = loadScenarioText(yaml, (path.parent_path() / "shown.yaml").string(), path.parent_path().string());
  const RunResult a = runScenario(s);
  const RunResult b = runScenario(again);
  EXPECT_EQ(summaryBody(s, a), summaryBody(again, b)) << rel << "\n" << yaml;
  EXPECT_EQ(s.warnings.size(), again.warnings.size()) << rel;
  ASSERT_EQ(a.rec.time_s.size(), b.rec.time_s.size()) << rel;
  EXPECT_EQ(a.rec.cell_voltage_V, b.rec.cell_voltage_V) << rel;
  EXPECT_EQ(a.rec.cell_temp_C, b.rec.cell_temp_C) << rel;
  ASSERT_EQ(a.events.size(), b.events.size()) << rel;
  for (size_t i = 0; i < a.events.size(); ++i) {
    EXPECT_EQ(a.events[i].time_s, b.events[i].time_s) << rel;
    if (a.events[i].kind != "config_warning") EXPECT_EQ(a.events[i].detail, b.events[i].detail) << rel;
  }
}

TEST(ScenarioShow, YamlFormRunsBitIdentical) {
  expectYamlRunsTheSame("faults/a_overcurrent.yaml", {{"load.laps", "1"}, {"faults.0.at_s", "30"},
                                                      {"expect", "{}"}});
  expectYamlRunsTheSame("bench_6s_ncr18650_2C.yaml", {});
  expectYamlRunsTheSame("balance/solar_4s3p_active.yaml", {{"run.duration_s", "300"}});
}

TEST(ScenarioShow, JsonNamesEveryValueAndTheWarnings) {
  const Scenario s = test::scenarioFromYaml(userPack("load: {current_A: 60}\nrun: {duration_s: 1}\n"));
  const std::string json = showJson(s);
  EXPECT_NE(json.find("\"pack.series\": {\"value\": \"24\", \"origin\": \"test.yaml:2\", \"stated\": true}"),
            std::string::npos) << json;
  EXPECT_NE(json.find("\"warnings\": [\n    \""), std::string::npos) << json;
}

// Item 3: a 24s4p pack with a 60 A load states no sensor: its range comes from its limits
// and its load, not from reference system A's +/-33 A.
TEST(ScenarioShow, UserPackSensorRangeCoversItsLoad) {
  const Scenario s = test::scenarioFromYaml(userPack("load: {current_A: 60}\nrun: {duration_s: 1}\n"));
  const double range_A = s.hardware.current_sense.zeroCode() * s.hardware.current_sense.lsb_A();
  EXPECT_NEAR(range_A, 75.0, 0.01);  // 1.25 x the 60 A peak (above 1.5 x the 30 A limit)
  EXPECT_EQ(originOf(s, "hardware.current_sense.amp_gain"),
            "default (a +/-75 A range: 1.25 x the load's peak 60 A, on the 5 mOhm shunt)");
  // The charge limit from the cell: 1C of 4 x 3.1 Ah.
  EXPECT_NEAR(s.bms.protection(bms::FaultId::OverCurrentCharge).threshold, 12.4, 1e-12);
  EXPECT_EQ(warningsWith(s, "overcurrent_discharge.threshold_A = 30 (default): the firmware table's limit"), 1u)
      << allWarnings(s);
  // The trip reads the real current, not a sensor rail at 33 A.
  const RunResult r = runScenario(s);
  std::string detail;
  for (const Event& e : r.events)
    if (e.kind == "fault_active" && detail.empty()) detail = e.detail;
  EXPECT_EQ(detail.rfind("overcurrent_discharge: current 60.", 0), 0u) << detail;
  // A warning is an event at t = 0.
  EXPECT_EQ(test::eventTime(r, "config_warning", "bms.protections.overcurrent_discharge"), 0.0);
}

TEST(ScenarioShow, CellRatingsSetTheLimits) {
  const Scenario s = test::scenarioFromYaml(
      "pack: {series: 24, parallel: 4, cell: {preset: ncr18650_3p1Ah, max_charge_C: 0.5, max_discharge_C: 3}}\n"
      "load: {current_A: 10}\nrun: {duration_s: 1}\n");
  EXPECT_NEAR(s.bms.protection(bms::FaultId::OverCurrentCharge).threshold, 6.2, 1e-12);
  EXPECT_NEAR(s.bms.protection(bms::FaultId::OverCurrentDischarge).threshold, 37.2, 1e-12);
  EXPECT_EQ(originOf(s, "bms.protections.overcurrent_discharge.threshold_A"),
            "default (the cell's max_discharge_C 3 x 3.1 Ah x 4 in parallel)");
  // Stated limits stay as stated, with no derived-default warning.
  const Scenario stated = test::scenarioFromYaml(
      "pack: {series: 24, parallel: 4, cell: {preset: ncr18650_3p1Ah, max_charge_C: 0.5}}\n"
      "bms: {protections: {overcurrent_charge: {threshold_A: 4}, overcurrent_discharge: {threshold_A: 20}}}\n"
      "load: {current_A: 10}\nrun: {duration_s: 1}\n");
  EXPECT_DOUBLE_EQ(stated.bms.protection(bms::FaultId::OverCurrentCharge).threshold, 4.0);
  EXPECT_EQ(warningsWith(stated, "overcurrent_"), 0u) << allWarnings(stated);
}

// A hardware section that states no relay, precharge or bus ADC still lists their values,
// each as a default; stating one changes it and names its line.
TEST(ScenarioShow, SectionsLeftOutListTheirDefaults) {
  const Scenario s = test::scenarioFromYaml(withHardware("  fuse: {rated_A: 30}\n"));
  EXPECT_EQ(originOf(s, "hardware.relay.open_delay_ms"), "default");
  EXPECT_EQ(originOf(s, "hardware.precharge.bus_capacitance_uF"), "default");
  EXPECT_EQ(originOf(s, "hardware.bus_adc.bits"), "default");
  EXPECT_EQ(s.hardware.bus_adc.code_max, 4095);
  const Scenario stated = test::scenarioFromYaml(withHardware("  relay: {open_delay_ms: 20}\n"));
  EXPECT_DOUBLE_EQ(stated.hardware.relay.open_delay_s, 0.020);
  EXPECT_NE(originOf(stated, "hardware.relay.open_delay_ms"), "default");
  EXPECT_EQ(originOf(stated, "hardware.precharge.r_ohm"), "default");
  // Reading the defaults leaves them exactly as they were.
  EXPECT_EQ(s.hardware.precharge.bus_capacitance_F, stated.hardware.precharge.bus_capacitance_F);
  EXPECT_EQ(s.hardware.relay.close_delay_s, stated.hardware.relay.close_delay_s);
}

TEST(ScenarioShow, BalancingHardwareStatesItsResistor) {
  const std::string err = test::yamlErrorOf(withHardware("  balancing: {board_node: b}\n"));
  EXPECT_NE(err.find("missing required key 'resistor_ohm'"), std::string::npos) << err;
}

// --- the warnings table: each check warns on its case and stays silent on a sound one ---

TEST(ScenarioWarnings, OverrideThatDropsADependence) {
  const Scenario flat = test::scenarioFromYaml(
      "pack: {series: 4, cell: {preset: lipo_5Ah, r0_ohm: 0.02}}\nload: {current_A: 1}\nrun: {duration_s: 1}\n");
  // A plain number keeps the preset's temperature law (R0 at its reference temperature)
  // but loses the SOC dependence.
  EXPECT_EQ(warningsWith(flat, "pack.cell.r0_ohm = 0.02 (test.yaml:1) replaces preset lipo_5Ah's curve, which depends "
                               "on SOC: this cell's"), 1u) << allWarnings(flat);
  // Written with its own temperature law of none: deliberate, not warned about.
  const Scenario own = test::scenarioFromYaml(
      "pack: {series: 4, cell: {preset: lipo_5Ah, r0_ohm: {poly: [0.02], arrhenius_K: 0, ref_temp_C: 25}}}\nload: {current_A: 1}\n"
      "run: {duration_s: 1}\n");
  EXPECT_EQ(warningsWith(own, "replaces"), 0u) << allWarnings(own);
  const Scenario curve = test::scenarioFromYaml(
      "pack: {series: 4, cell: {preset: lipo_5Ah, r0_ohm: {x: [0, 1], y: [0.02, 0.01], arrhenius_K: 2000, "
      "ref_temp_C: 25}}}\nload: {current_A: 1}\nrun: {duration_s: 1}\n");
  EXPECT_EQ(warningsWith(curve, "replaces"), 0u) << allWarnings(curve);
  // A --set that puts a single value where the file has a table.
  const std::string yaml = test::simpleCellYaml() + "load: {points: {time_s: [0, 5], current_A: [1, 2]}}\n"
                           "run: {duration_s: 10}\n";
  const Scenario set = loadScenarioWithOverrides(yaml, {{"pack.cell.ocv_V", "3.7"}}, "test.yaml", test::scenarioDir());
  EXPECT_EQ(warningsWith(set, "pack.cell.ocv_V: the curve over soc of test.yaml:9 is replaced by the single value 3.7 "
                              "(--set pack.cell.ocv_V=3.7)"), 1u) << allWarnings(set);
}

TEST(ScenarioWarnings, LimitNearOrBeyondTheSensor) {
  // +/-33 A sensor (5 mOhm, gain 10, 3.3 V, 16 bits), 30 A limit: within 10 %.
  const std::string sensor = "hardware: {current_sense: {shunt_ohm: 0.005, amp_gain: 10}}\n";
  const Scenario near = test::scenarioFromYaml(userPack(sensor + "load: {current_A: 10}\nrun: {duration_s: 1}\n"));
  EXPECT_EQ(warningsWith(near, "bms.protections.overcurrent_discharge.threshold_A = 30 (default) is within 10 % of the "
                               "current sensor's +/-33 A"), 1u) << allWarnings(near);
  const Scenario beyond = test::scenarioFromYaml(userPack(sensor + "load: {current_A: 60}\nrun: {duration_s: 1}\n"));
  EXPECT_EQ(warningsWith(beyond, "load (test.yaml:"), 1u) << allWarnings(beyond);
  EXPECT_EQ(warningsWith(beyond, "peaks at 60 A, beyond the current sensor's +/-33 A"), 1u) << allWarnings(beyond);
  const Scenario fine = test::scenarioFromYaml(
      userPack(sensor + "bms: {protections: {overcurrent_discharge: {threshold_A: 20}}}\n"
                        "load: {current_A: 10}\nrun: {duration_s: 1}\n"));
  EXPECT_EQ(warningsWith(fine, "sensor"), 0u) << allWarnings(fine);
  // A limit at or past the sensor's range stays an error.
  EXPECT_NE(test::yamlErrorOf(userPack(sensor + "bms: {protections: {overcurrent_discharge: {threshold_A: 60}}}\n"
                                                "load: {current_A: 10}\nrun: {duration_s: 1}\n"))
                .find("beyond the current sensor's range"),
            std::string::npos);
}

// A BQ76952 judges its own current across its shunt. Its data-sheet defaults (OCD1 8 mV,
// OCC 4 mV) are 1.6 A and 0.8 A on a 5 mOhm shunt: below a 10 A BMS limit and a 3 A load,
// the pack tripped on the part's FAULT line at 0.07 s with nothing naming the part's
// threshold. Each such threshold is a warning with its amps and what it undercuts; a
// stated threshold above both is none.
TEST(ScenarioWarnings, AMonitorPartsCurrentLimitBelowTheBmsOrTheLoad) {
  const std::string pack =
      "name: p16s\npack: {series: 16, initial_soc: 0.7, cell: {preset: ncr18650_3p1Ah}}\n"
      "bms: {protections: {overcurrent_discharge: {threshold_A: 10}, overcurrent_charge: {threshold_A: 3}}}\n"
      "load: {current_A: 3}\nrun: {duration_s: 1}\n";
  const Scenario defaults = test::scenarioFromYaml(pack + "hardware: {afe: {model: bq76952, cells_per_device: 16}}\n");
  EXPECT_EQ(warningsWith(defaults, "hardware.afe.protection.ocd1_mV = 8 (the part's default): 1.6 A on the 5 mOhm shunt, "
                                   "below bms.protections.overcurrent_discharge.threshold_A 10 A and the load's peak 3 A: "
                                   "the BQ76952 trips the pack first"), 1u) << allWarnings(defaults);
  EXPECT_EQ(warningsWith(defaults, "hardware.afe.protection.occ_mV = 4 (the part's default): 0.8 A on the 5 mOhm shunt, "
                                   "below bms.protections.overcurrent_charge.threshold_A 3 A:"), 1u) << allWarnings(defaults);
  EXPECT_EQ(warningsWith(defaults, "scd_mV"), 0u) << "100 mV is 20 A: above both";
  const Scenario stated = test::scenarioFromYaml(
      pack + "hardware: {afe: {model: bq76952, cells_per_device: 16, protection: {ocd1_mV: 60, occ_mV: 20}}}\n");
  EXPECT_EQ(warningsWith(stated, "trips the pack first"), 0u) << allWarnings(stated);
  const Scenario low = test::scenarioFromYaml(
      pack + "hardware: {afe: {model: bq76952, cells_per_device: 16, protection: {ocd1_mV: 40, occ_mV: 20}}}\n");
  EXPECT_EQ(warningsWith(low, "hardware.afe.protection.ocd1_mV = 40: 8 A on the 5 mOhm shunt, below "
                              "bms.protections.overcurrent_discharge.threshold_A 10 A:"), 1u) << allWarnings(low);
}

// Balancing resistors with no policy to switch them: packsim's core balances only with
// a bms.balancing section. The warning's claim is checked: two resistor values give the
// same run. With the policy, or a BQ76952 balancing on its own, there is no warning.
TEST(ScenarioWarnings, BalancingResistorsThatNothingSwitches) {
  const std::string pack =
      "name: p6s\npack: {series: 6, initial_soc: 0.7, cell: {preset: ncr18650_3p1Ah}, spread: {initial_soc_sd: 0.05}}\n"
      "load: {current_A: 0}\nrun: {duration_s: 30}\n";
  const std::string said = "no balancing policy switches these resistors";
  const auto with = [&](const std::string& extra) { return test::scenarioFromYaml(pack + extra); };
  const Scenario none = with("hardware: {balancing: {resistor_ohm: 33}}\n");
  EXPECT_EQ(warningsWith(none, "hardware.balancing.resistor_ohm = 33 (test.yaml:5): no balancing policy"), 1u) << allWarnings(none);
  EXPECT_EQ(warningsWith(none, said), 1u) << allWarnings(none);
  const RunResult a = runScenario(none), b = runScenario(with("hardware: {balancing: {resistor_ohm: 100}}\n"));
  EXPECT_EQ(a.rec.soc_truth_mean, b.rec.soc_truth_mean);
  EXPECT_EQ(a.rec.cell_soc, b.rec.cell_soc);
  const Scenario policy = with("hardware: {balancing: {resistor_ohm: 33}}\nbms: {balancing: {when: always}}\n");
  EXPECT_EQ(warningsWith(policy, said), 0u) << allWarnings(policy);
  const RunResult c = runScenario(policy);
  EXPECT_NE(a.rec.cell_soc, c.rec.cell_soc) << "with the policy the resistors bleed";
  const Scenario own = test::scenarioFromYaml(
      "name: p6s\npack: {series: 6, initial_soc: 0.7, cell: {preset: ncr18650_3p1Ah}}\n"
      "hardware: {afe: {model: bq76952, autonomous_balancing: {when: charging}}, balancing: {resistor_ohm: 33}}\n"
      "load: {current_A: 0}\nrun: {duration_s: 1}\n");
  EXPECT_EQ(warningsWith(own, said), 0u) << allWarnings(own);
}

// userPack's 24 groups with one cell each.
std::string userString(const std::string& extra) {
  std::string y = userPack(extra);
  y.replace(y.find("parallel: 4"), 11, "parallel: 1");
  return y;
}

TEST(ScenarioWarnings, SeriesGroupFarFromEveryThermistor) {
  // 24 groups, the default four thermistors at groups 1, 7, 13, 19: group 24 is 5 away.
  const std::string linked = "thermal: {cell_to_cell_W_per_K: 0.5}\n";  // reach 4 against 0.04 W/K to ambient
  const Scenario far = test::scenarioFromYaml(userString(linked + "load: {current_A: 10}\nrun: {duration_s: 1}\n"));
  EXPECT_EQ(warningsWith(far, "hardware.thermistors.at_groups = [1, 7, 13, 19] (default (up to 4 spread over the "
                              "string)): series group 24 (1-based) is more than 4 groups"), 1u) << allWarnings(far);
  const Scenario covered = test::scenarioFromYaml(
      userString(linked + "hardware: {thermistors: {at_groups: [1, 8, 16, 24]}}\nload: {current_A: 10}\nrun: {duration_s: 1}\n"));
  EXPECT_EQ(warningsWith(covered, "thermistor"), 0u) << allWarnings(covered);
}

// With parallel cells the reach counts cells: a thermistor sits on its group's first
// cell and the cells are linked one after the other (24s4p: cells 1, 29, 61 and 93 carry
// the four thermistors; a cell more than 4 links from all of them is unseen, although
// every group is within 4 groups of one).
TEST(ScenarioWarnings, ParallelCellsFarFromEveryThermistorsCell) {
  const Scenario s = test::scenarioFromYaml(userPack("thermal: {cell_to_cell_W_per_K: 0.5}\n"
                                                     "hardware: {thermistors: {at_groups: [1, 8, 16, 24]}}\n"
                                                     "load: {current_A: 10}\nrun: {duration_s: 1}\n"));
  EXPECT_EQ(warningsWith(s, ": cells 6-24, 34-56, 66-88 (1-based, 4 to a group; each thermistor sits on its group's "
                            "first cell) are more than 4 cells from every thermistor"), 1u) << allWarnings(s);
  EXPECT_EQ(warningsWith(s, "thermistor"), 1u) << allWarnings(s);
}

// Without cell-to-cell conductances (the default) no heat reaches a thermistor from another
// cell: every cell but the thermistors' own is unseen. A user's 24s4p pack with ten
// thermistors was told only 18 of its 86 other cells were, and a 30 W internal short in
// cell 50, the neighbour of group 13's thermistor cell, reached 110 C with that thermistor
// at 30.9 C and no trip.
TEST(ScenarioWarnings, NoCellToCellConductanceLeavesEveryOtherCellUnseen) {
  const Scenario s = test::scenarioFromYaml(
      userPack("hardware: {thermistors: {at_groups: [1, 8, 16, 24]}}\nload: {current_A: 10}\nrun: {duration_s: 1}\n"));
  EXPECT_EQ(thermistorReachLinks(s), 0);
  EXPECT_EQ(warningsWith(s, ": cells 2-28, 30-60, 62-92, 94-96 (1-based, 4 to a group; each thermistor sits on its "
                            "group's first cell) carry no thermistor; thermal.cell_to_cell_W_per_K = 0 (default): no heat flows from cell to "
                            "cell, so a thermistor sees only the cell it sits on: a hot cell there goes unseen"), 1u)
      << allWarnings(s);
}

// The reach against the plant's own thermal network: a hot cell in the middle of a 41-cell
// string at rest, run to steady state (about 10 time constants of the cell's heat capacity
// over its conductances); the cell `reach` links away rises by at least the seen fraction
// of the hot cell's rise, the next one by less. Three conductances: weak, middling, and
// strong enough for the fixed cap of 4.
TEST(ScenarioWarnings, ThermistorReachIsWhereTheSteadyRiseFallsBelowATenth) {
  for (const double g : {0.02, 0.2, 1.0}) {
    const Scenario s = test::scenarioFromYaml(
        "pack: {series: 41, cell: {preset: ncr18650_3p1Ah, g_ambient_W_per_K: 0.15}}\n"
        "thermal: {cell_to_cell_W_per_K: " + std::to_string(g) + "}\n"
        "ambient: {temp_C: 25}\nload: {current_A: 0}\nrun: {duration_s: 6000}\nbms: {tick_ms: 1000}\n"
        "output: {interval_s: 100}\nfaults: [{kind: hot_cell, cell: 21, heat_W: 5, at_s: 0}]\n");
    const int reach = thermistorReachLinks(s);
    const RunResult r = runScenario(s);
    const size_t cells = 41, last = r.rec.time_s.size() - 1;
    auto rise = [&](int cell) { return r.rec.cell_temp_C[last * cells + cell - 1] - 25.0; };
    SCOPED_TRACE("g " + std::to_string(g) + ", reach " + std::to_string(reach));
    ASSERT_GT(rise(21), 5.0);  // a rise well above the noise of a steady state
    if (reach < kThermistorReachLinks) {
      EXPECT_GE(rise(21 + reach), kThermistorSeenFraction * rise(21));
      EXPECT_LT(rise(21 + reach + 1), kThermistorSeenFraction * rise(21));
    } else {
      EXPECT_GE(rise(21 + reach), kThermistorSeenFraction * rise(21));
    }
  }
}

// A rest threshold inside the current sensor's noise: 0.2 A against 0.05 A rms is 4 sigma,
// a reading past it every 0.1 s / erfc(4 / sqrt 2) = 26 min, shorter than ten of the
// SOC's 30 min rests (and of balancing's 10 min ones when it balances at rest). At
// 0.03 A rms (6.7 sigma) a reading passes it about once in 2,000 years of ticks: no warning.
TEST(ScenarioWarnings, ARestThresholdTheCurrentNoiseCrosses) {
  const std::string pack = userString("hardware: {current_sense: {noise_A_rms: 0.05}}\n"
                                      "load: {current_A: 10}\nrun: {duration_s: 1}\nbms: {tick_ms: 100");
  const Scenario soc = test::scenarioFromYaml(pack + "}\n");
  EXPECT_EQ(warningsWith(soc, "bms.soc.rest_current_A = 0.2 (default) is 4 times the current sensor's 0.05 A rms noise "
                              "(hardware.current_sense.noise_A_rms, test.yaml:"), 1u) << allWarnings(soc);
  EXPECT_EQ(warningsWith(soc, "): at the 0.1 s BMS tick a reading at rest passes it about every 26 min on average, and "
                              "each one restarts the 30 min of rest the firmware waits for before re-anchoring the SOC "
                              "on the OCV"), 1u) << allWarnings(soc);
  EXPECT_EQ(warningsWith(soc, "bms.balancing.rest_current_A"), 0u) << allWarnings(soc);  // no balancing at rest
  std::string bleeding = pack + ", balancing: {when: rest}}\n";
  bleeding.replace(bleeding.find("hardware: {"), 11, "hardware: {balancing: {resistor_ohm: 33}, ");
  const Scenario balancing = test::scenarioFromYaml(bleeding);
  EXPECT_EQ(warningsWith(balancing, "before balancing at rest"), 1u) << allWarnings(balancing);
  std::string quiet = pack + "}\n";
  quiet.replace(quiet.find("noise_A_rms: 0.05"), 17, "noise_A_rms: 0.03");
  EXPECT_EQ(warningsWith(test::scenarioFromYaml(quiet), "rest_current_A"), 0u);
}

// The warning's rate against the sensor model itself: 400,000 conversions of 0 A on a
// 16-bit, 0.05 A rms channel (quantised, as the firmware reads it), the share of readings
// at or above 0.2 A in magnitude against erfc(4 / sqrt 2) = 6.3e-5 (about 25 expected:
// within 3 sigma of a Poisson count).
TEST(ScenarioWarnings, TheRestBreakRateIsTheSensorsOwn) {
  CurrentSense cs;
  cs.shunt_ohm = 0.0005;
  cs.amp_gain = 50.0;
  cs.noise_A_rms = 0.05;
  const AdcChannel ch = cs.channel();
  Rng rng(7);
  const int n = 400000;
  int past = 0;
  for (int i = 0; i < n; ++i) {
    const double amps = (ch.convert(0.0, rng) - cs.zeroCode()) * cs.lsb_A();
    past += std::fabs(amps) >= 0.2;
  }
  const double expected = n * 0.1 / meanTimeBetweenNoiseBreaks_s(0.2, 0.05, 0.1);
  EXPECT_NEAR(expected, n * std::erfc(4.0 / std::sqrt(2.0)), 1e-9);
  EXPECT_NEAR(past, expected, 3.0 * std::sqrt(expected) + 1.0) << "lsb " << cs.lsb_A() << " A";
  EXPECT_TRUE(std::isinf(meanTimeBetweenNoiseBreaks_s(0.2, 0.0, 0.1)));
}

TEST(ScenarioWarnings, ImplausibleMagnitudesForThePack) {
  // 300 A from one 5 Ah string: 60C, above any plausible rating but below the 100C the
  // loader refuses outright (milliamps read as amps: ScenarioErrors).
  const Scenario mA = test::scenarioFromYaml(
      "pack: {series: 4, cell: {preset: lipo_5Ah}}\nload: {current_A: 300}\nrun: {duration_s: 1}\n");
  EXPECT_EQ(warningsWith(mA, "a peak discharge of 300 A is 60C per cell"), 1u) << allWarnings(mA);
  // Watts per cell: 4 kW from 4 LiPo cells.
  const Scenario watts = test::scenarioFromYaml(
      "pack: {series: 4, cell: {preset: lipo_5Ah}}\nload: {power_W: 4000}\nrun: {duration_s: 1}\n");
  EXPECT_EQ(warningsWith(watts, "W per cell"), 1u) << allWarnings(watts);
  // Above the cell's own rating.
  const Scenario rated = test::scenarioFromYaml(
      "pack: {series: 4, parallel: 2, cell: {preset: lipo_5Ah, max_discharge_C: 2}}\n"
      "bms: {protections: {overcurrent_discharge: {threshold_A: 40}}}\n"
      "load: {current_A: 30}\nrun: {duration_s: 1}\n");
  EXPECT_EQ(warningsWith(rated, "is 3C per cell (15 A each"), 1u) << allWarnings(rated);
  const Scenario sound = test::scenarioFromYaml(
      "pack: {series: 4, cell: {preset: lipo_5Ah}}\nload: {current_A: 10}\nrun: {duration_s: 1}\n");
  EXPECT_EQ(warningsWith(sound, "per cell"), 0u) << allWarnings(sound);
}

TEST(ScenarioWarnings, BalancingWithoutABoardNode) {
  const Scenario bare = test::scenarioFromYaml(withHardware("  balancing: {resistor_ohm: 47}\n"));
  EXPECT_EQ(warningsWith(bare, "have no board_node"), 1u) << allWarnings(bare);
  const Scenario board = test::scenarioFromYaml(withHardware("  balancing: {resistor_ohm: 47, board_node: b}\n") +
                                                "thermal: {nodes: [{name: b, heat_capacity_J_per_K: 20}]}\n");
  EXPECT_EQ(warningsWith(board, "board_node"), 0u) << allWarnings(board);
}

// A run ends at a BMS tick: 2.5 s at a 1 s tick runs to 2 s (the recording's last sample
// says so), and a profile of 10.25 s at a 100 ms tick (the default duration) to 10.2 s.
// A whole number of ticks, or a floating-point hair from one, is not warned about.
TEST(ScenarioWarnings, AnEndBetweenTwoTicks) {
  const std::string cell = test::simpleCellYaml();
  const Scenario cut = test::scenarioFromYaml(cell + "load: {current_A: 1}\nrun: {duration_s: 2.5}\nbms: {tick_ms: 1000}\n");
  EXPECT_EQ(warningsWith(cut, "run.duration_s = 2.5 (test.yaml:"), 1u) << allWarnings(cut);
  EXPECT_EQ(warningsWith(cut, "is not a whole number of BMS ticks (bms.tick_ms 1000): the run ends at its last tick, 2 s, "
                              "0.5 s early"), 1u) << allWarnings(cut);
  const RunResult r = runScenario(cut);
  EXPECT_DOUBLE_EQ(r.rec.time_s.back(), 2.0);
  EXPECT_DOUBLE_EQ(r.summary.duration_s, 2.0);
  const Scenario profile = test::scenarioFromYaml(
      cell + "load: {segments: [{duration_s: 10, current_A: 1}, {duration_s: 0.25, current_A: 2}]}\nbms: {tick_ms: 100}\n");
  EXPECT_EQ(warningsWith(profile, "run.duration_s = 10.25 (default: the load profile's length) is not a whole number of "
                                  "BMS ticks (bms.tick_ms 100): the run ends at its last tick, 10.2 s, 0.05 s early"), 1u)
      << allWarnings(profile);
  for (const char* whole : {"run: {duration_s: 3}\nbms: {tick_ms: 1000}\n", "run: {duration_s: 0.7}\n",
                            "run: {duration_s: 2620.01}\n"}) {
    const Scenario s = test::scenarioFromYaml(cell + "load: {current_A: 1}\n" + whole);
    EXPECT_EQ(warningsWith(s, "whole number of BMS ticks"), 0u) << whole << allWarnings(s);
  }
}

// Every bundled scenario loads without a spurious warning: system B's three replace the
// NCR18650 preset's R0 curve by a curve of their own ({poly: [0.030], arrhenius_K: 0}),
// deliberately, and are not warned about (OverrideThatDropsADependence: a plain number is).
// The true warnings of thermistor reach: system B (28 modules of 15 cells, seven
// thermistors, each on its module's first cell: cells 1, 61, 121, 196, 256, 331, 406; its
// 0.05 W/K between cells against 0.04 W/K to ambient reaches 2 cells) leaves most cells
// unseen; the Formula-Student pack (96s3p, a thermistor on every second group from group
// 1) leaves its last cell, 288, five cells from the one on group 95; the two bench packs
// without cell-to-cell conductances (the 6s balancing bench and what extends it, the 4s3p
// active balancer) have no cell but a thermistor's own watched.
TEST(ScenarioWarnings, BundledScenarios) {
  for (const auto& e : fs::recursive_directory_iterator(test::scenarioDir())) {
    const fs::path p = e.path();
    const std::string rel = p.lexically_relative(test::scenarioDir()).string();
    if (p.extension() != ".yaml" || rel.rfind("cells/", 0) == 0 || rel.rfind("profiles/", 0) == 0) continue;
    if (rel.rfind("firmware/", 0) == 0) continue;  // needs the example firmware library
    const Scenario s = loadScenarioFile(p.string());
    const bool systemB = s.pack.series == 28 && s.pack.parallel == 15;
    const bool fs96 = s.pack.series == 96 && s.pack.parallel == 3;
    const bool unlinked = s.thermal.cell_to_cell_W_per_K == 0.0;
    const size_t reach = warningsWith(s, "goes unseen");
    EXPECT_EQ(reach, systemB || fs96 || unlinked ? 1u : 0u) << rel << "\n" << allWarnings(s);
    // The current sensors of systems B (0.05 A rms at a 0.1 s tick) and D (0.3 A rms), the
    // Formula-Student pack's (0.1 A rms) and the 4s3p active balancer's (0.05 A rms at
    // 1 s) cross the SOC's default 0.2 A rest threshold more often than every ten rests.
    const bool systemD = s.pack.series == 110, activeBalancer = s.pack.series == 4 && s.pack.parallel == 3;
    const size_t rest = warningsWith(s, "bms.soc.rest_current_A = 0.2 (default) is ");
    EXPECT_EQ(rest, systemB || systemD || fs96 || activeBalancer ? 1u : 0u) << rel << "\n" << allWarnings(s);
    if (systemB)
      EXPECT_EQ(warningsWith(s, ": cells 4-58, 64-118, 124-193, 199-253, 259-328, 334-403, 409-420 (1-based, 15 to a group; "), 1u)
          << rel << "\n" << allWarnings(s);
    if (fs96) EXPECT_EQ(warningsWith(s, ": cell 288 (1-based, 3 to a group; "), 1u) << rel << "\n" << allWarnings(s);
    if (unlinked) EXPECT_EQ(warningsWith(s, "no heat flows from cell to cell"), 1u) << rel << "\n" << allWarnings(s);
    EXPECT_EQ(s.warnings.size(), reach + rest) << rel << "\n" << allWarnings(s);
  }
}

}  // namespace
}  // namespace packsim
