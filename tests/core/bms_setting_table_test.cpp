// The BMS settings table (bms/bms_settings.def): every row is read from its key, in its
// range, converted once into firmware units and flashed; its default is the firmware's;
// docs/scenario.md lists it as the table says.
#include <gtest/gtest.h>

#include <bms/bms_config.hpp>
#include <cmath>
#include <fstream>
#include <set>
#include <sstream>

#include "core/scenario/bms_setting_table.hpp"
#include "core/scenario/provenance.hpp"
#include "core/sim/bms_bridge.hpp"
#include "test_support.hpp"

namespace packsim {
namespace {

std::string scenarioWithBms(const std::string& bmsYaml) {
  return test::simpleCellYaml(4) + test::kSimpleLoadYaml + "bms:\n" + bmsYaml;
}

// A value of the row's key that is not its default and lies in its range.
double otherValue(const SettingRow& r) {
  switch (r.kind) {
    case SettingKind::Flag: return r.def != 0.0 ? 0.0 : 1.0;
    case SettingKind::Enable: return 0.0;  // stating the section turns it on; `enabled: false` turns it off
    case SettingKind::Choice: return r.def == 0.0 ? 1.0 : 0.0;
    case SettingKind::Integer: return r.def < r.hi ? r.def + 1.0 : r.def - 1.0;
    case SettingKind::Number: break;
  }
  // A quarter of the way to the top of the range; down to keep a stop or resume
  // threshold below its start (a rule across keys).
  const std::string leaf = r.leaf();
  if (leaf == "stop_delta_mV" || leaf == "board_resume_C") return (r.lo + r.def) / 2.0;
  return r.def * 0.75 + r.hi * 0.25;
}

std::string yamlText(const SettingRow& r, double v) {
  switch (r.kind) {
    case SettingKind::Flag:
    case SettingKind::Enable: return v != 0.0 ? "true" : "false";
    case SettingKind::Choice: return r.choices[static_cast<size_t>(v)];
    case SettingKind::Integer: return std::to_string(static_cast<long>(v));
    case SettingKind::Number: break;
  }
  return numberText(v);
}

// `key: value` nested under its sections, as a scenario writes it under bms:.
std::string nestedYaml(const std::string& key, const std::string& value) {
  std::string out, indent = "  ";
  std::string rest = key;
  for (size_t dot = rest.find('.'); dot != std::string::npos; dot = rest.find('.')) {
    out += indent + rest.substr(0, dot) + ":\n";
    indent += "  ";
    rest = rest.substr(dot + 1);
  }
  // Balancing stated is balancing on, which needs balancing hardware: off for the others.
  if (key.rfind("balancing.", 0) == 0 && rest != "enabled") out += indent + "enabled: false\n";
  return out + indent + rest + ": " + value + "\n";
}

TEST(BmsSettingTable, KeysAreUniqueDefaultsInRangeAndTheFirmwareDefaultIsTheRowsDefault) {
  std::set<std::string> keys;
  const bms::Config fw = bms::defaultConfig(4, 2);
  for (const SettingRow& r : settingRows()) {
    SCOPED_TRACE(r.key);
    EXPECT_TRUE(keys.insert(r.key).second) << "a key twice";
    EXPECT_GE(r.def, r.lo);
    EXPECT_LE(r.def, r.hi);
    EXPECT_FALSE(r.loOpen && r.def == r.lo);
    EXPECT_GT(std::string(r.doc).size(), 10u) << "every row documents itself";
    // The loader's conversion of the default is what the firmware flashes by default.
    bms::Config c{};
    r.set(c, r.def);
    EXPECT_EQ(r.get(c), r.get(fw));
  }
  for (const char* key : {"comm_loss_count", "precharge.retries", "soc.estimator", "soc.ekf.voltage_sd_mV", "balancing.when"})
    EXPECT_TRUE(keys.count(key)) << key;
}

// Hand-computed conversions: each key's unit to the firmware's, without mV -> V -> mV.
TEST(BmsSettingTable, KeyValuesReachTheFirmwareInItsUnits) {
  const Scenario s = test::scenarioFromYaml(scenarioWithBms(
      "  weld_settle_ms: 75\n"
      "  charge_full_cell_V: 4.15\n"
      "  comm_loss_count: 9\n"
      "  precharge: {done_delta_V: 2.5, done_current_A: 0.125, retries: 7}\n"
      "  soc: {rest_s: 12.5, rest_current_A: 0.35, estimator: ekf, ekf: {soc_walk_per_sqrt_h: 0.06, voltage_sd_mV: 4.5}}\n"
      "  balancing: {enabled: false, when: rest, start_delta_mV: 37, stop_delta_mV: 12, min_cell_V: 3.456,\n"
      "              board_max_C: 65.5, board_resume_C: -12.5, rest_s: 2, period_ms: 250, average_readings: 8}\n"));
  const bms::Config c = makeBmsConfig(s);
  EXPECT_EQ(c.weldSettle_ms, 75u);
  EXPECT_EQ(c.chargeFullCell_mV, 4150);
  EXPECT_EQ(c.afe.commLossCount, 9);
  EXPECT_EQ(c.rules[static_cast<int>(bms::FaultId::CommLoss)].threshold, 8) << "trips at the 9th bad read";
  EXPECT_TRUE(c.precharge.enabled) << "a stated precharge section is on";
  EXPECT_EQ(c.precharge.doneDelta_mV, 2500u);
  EXPECT_EQ(c.precharge.doneCurrent_mA, 125);
  EXPECT_EQ(c.precharge.retries, 7);
  EXPECT_EQ(c.precharge.timeout_ms, 2000u) << "unstated: the default";
  EXPECT_EQ(c.soc.rest_ms, 12500u);
  EXPECT_EQ(c.soc.restCurrent_mA, 350);
  EXPECT_EQ(c.soc.estimator, bms::SocEstimator::Ekf);
  EXPECT_FLOAT_EQ(c.soc.ekf.socSdPerSqrtS, 0.001f);  // 0.06 per sqrt(h) = 0.001 per sqrt(s)
  EXPECT_FLOAT_EQ(c.soc.ekf.voltageSd_mV, 4.5f);
  EXPECT_FALSE(c.balance.enabled);
  EXPECT_EQ(c.balance.when, bms::BalanceWhen::Rest);
  EXPECT_EQ(c.balance.startDelta_mV, 37);
  EXPECT_EQ(c.balance.stopDelta_mV, 12);
  EXPECT_EQ(c.balance.minCell_mV, 3456);
  EXPECT_EQ(c.balance.boardMax_dC, 655);
  EXPECT_EQ(c.balance.boardResume_dC, -125);
  EXPECT_EQ(c.balance.rest_ms, 2000u);
  EXPECT_EQ(c.balance.period_ms, 250u);
  EXPECT_EQ(c.balance.averageReadings, 8);
}

// Every row: a stated value other than the default reaches the flashed image, and
// `show` names the line that set it; unstated, `show` lists the default.
TEST(BmsSettingTable, EveryRowIsReadFlashedAndShown) {
  const bms::Config defaults = makeBmsConfig(test::scenarioFromYaml(test::simpleCellYaml(4) + test::kSimpleLoadYaml));
  for (const SettingRow& r : settingRows()) {
    SCOPED_TRACE(r.key);
    const double v = otherValue(r);
    const Scenario s = test::scenarioFromYaml(scenarioWithBms(nestedYaml(r.key, yamlText(r, v))));
    const bms::Config c = makeBmsConfig(s);
    bms::Config expected{};
    r.set(expected, v);
    EXPECT_EQ(r.get(c), r.get(expected));
    if (r.kind != SettingKind::Enable) EXPECT_NE(r.get(c), r.get(defaults)) << "the test's value must differ from the default";
    ASSERT_TRUE(s.provenance);
    const std::string key = std::string("bms.") + r.key;
    EXPECT_EQ(s.provenance->originOf(key).rfind("test.yaml:", 0), 0u) << s.provenance->originOf(key);
  }
  const Scenario plain = test::scenarioFromYaml(test::simpleCellYaml(4) + test::kSimpleLoadYaml);
  ASSERT_TRUE(plain.provenance);
  for (const SettingRow& r : settingRows()) {
    const ProvenanceEntry* e = plain.provenance->find(std::string("bms.") + r.key);
    ASSERT_NE(e, nullptr) << r.key;
    EXPECT_EQ(e->origin, "default");
    EXPECT_EQ(e->value, r.defaultText());
  }
}

TEST(BmsSettingTable, BadValuesNameTheKeyItsRangeOrTheClosestKey) {
  EXPECT_NE(test::yamlErrorOf(scenarioWithBms("  balancing: {enabled: false, start_delta_mV: 5000}\n"))
                .find("bms.balancing.start_delta_mV"),
            std::string::npos);
  EXPECT_NE(test::yamlErrorOf(scenarioWithBms("  balancing: {enabled: false, start_delta_mV: 5000}\n")).find("[1, 2000]"),
            std::string::npos);
  const std::string misspelt = test::yamlErrorOf(scenarioWithBms("  balancing: {enabled: false, start_delta_mv: 20}\n"));
  EXPECT_NE(misspelt.find("start_delta_mV"), std::string::npos) << misspelt;
  const std::string when = test::yamlErrorOf(scenarioWithBms("  balancing: {enabled: false, when: charge}\n"));
  EXPECT_NE(when.find("charging"), std::string::npos) << when;
  EXPECT_NE(test::yamlErrorOf(scenarioWithBms("  balancing: {enabled: false, start_delta_mV: 20, stop_delta_mV: 30}\n"))
                .find("must not exceed start_delta_mV"),
            std::string::npos);
  EXPECT_NE(test::yamlErrorOf(scenarioWithBms("  precharge: {done_current_A: 0}\n")).find("(0, 100000]"), std::string::npos);
}

TEST(BmsSettingTable, ScenarioDocHoldsTheGeneratedTable) {
  std::ifstream in(test::scenarioDir() + "/../docs/scenario.md");
  std::stringstream ss;
  ss << in.rdbuf();
  EXPECT_NE(ss.str().find(settingsDocTable()), std::string::npos)
      << "docs/scenario.md's BMS settings table must read exactly:\n" << settingsDocTable();
}

}  // namespace
}  // namespace packsim
