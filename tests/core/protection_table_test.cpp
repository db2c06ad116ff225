// The protection table (bms/bms_faults.hpp + core/scenario/protection_table.hpp) is
// complete and consistent, and every consumer follows it: the loader reads each row's
// keys in its unit and range, the bridge scales each row into its own firmware rule,
// and the event text reads as it did before the table existed.
#include <gtest/gtest.h>

#include <bms/bms_config.hpp>
#include <algorithm>
#include <cmath>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>

#include "core/scenario/protection_table.hpp"
#include "core/sim/bms_bridge.hpp"
#include "test_support.hpp"

namespace packsim {
namespace {

using F = bms::FaultId;

std::string fmt(double v) {
  std::ostringstream os;
  os.precision(17);
  os << v;
  return os.str();
}

TEST(ProtectionTable, EveryFaultHasOneRowOnBothSidesUnderItsOwnId) {
  ASSERT_EQ(protectionSpecs().size(), bms::kFaultCount);
  std::set<std::string> names;
  for (uint8_t i = 0; i < bms::kFaultCount; ++i) {
    const auto id = static_cast<F>(i);
    EXPECT_EQ(static_cast<int>(bms::faultRow(id).id), i);
    EXPECT_EQ(static_cast<int>(protectionSpecs()[i].id), i);
    const std::string name = bms::faultName(id);
    EXPECT_TRUE(std::regex_match(name, std::regex("[a-z][a-z0-9]*(_[a-z0-9]+)*"))) << name;
    EXPECT_TRUE(names.insert(name).second) << "duplicate name (YAML key) " << name;
  }
  EXPECT_STREQ(bms::faultName(F::Count), "unknown");
}

// The SI unit and scale agree with the firmware unit of the row they scale into.
TEST(ProtectionTable, SiUnitAndScaleMatchTheFirmwareUnit) {
  for (const ProtectionSpec& s : protectionSpecs()) {
    const bms::FaultRow& fw = bms::faultRow(s.id);
    SCOPED_TRACE(fw.name);
    // A weld current is mA in bms::Config::weldCurrent_mA; its rule is a flag.
    const bms::FaultUnit unit = s.use == ThresholdUse::WeldCurrent ? bms::FaultUnit::mA : fw.unit;
    if (s.use == ThresholdUse::WeldCurrent) EXPECT_EQ(fw.unit, bms::FaultUnit::Flag);
    switch (unit) {
      case bms::FaultUnit::mV: EXPECT_STREQ(s.unit, "V"); EXPECT_EQ(s.scale, 1000.0); break;
      case bms::FaultUnit::mA: EXPECT_STREQ(s.unit, "A"); EXPECT_EQ(s.scale, 1000.0); break;
      case bms::FaultUnit::dC: EXPECT_STREQ(s.unit, "C"); EXPECT_EQ(s.scale, 10.0); break;
      case bms::FaultUnit::Flag:
      case bms::FaultUnit::Replies: EXPECT_EQ(s.use, ThresholdUse::None); EXPECT_STREQ(s.unit, ""); break;
    }
    if (s.use != ThresholdUse::None) {
      EXPECT_LT(s.min, s.max);
      const ProtectionConfig d = defaultProtection(s.id);
      EXPECT_TRUE(d.threshold > s.min || (!s.minOpen && d.threshold == s.min)) << d.threshold;
      EXPECT_LE(d.threshold, s.max);
    }
  }
}

// The SI defaults as they were written by hand before the table (scenario.hpp, up to
// issue 15): the derivation from the firmware rows reproduces them bit for bit.
TEST(ProtectionTable, SiDefaultsAreTheHistoricalOnes) {
  const struct {
    F id;
    ProtectionConfig p;
  } before[] = {
      {F::CellOverVoltage, {true, 4.25, 0.05, 0.5}},        {F::CellUnderVoltage, {true, 3.0, 0.1, 0.5}},
      {F::OverCurrentDischarge, {true, 30.0, 1.0, 0.1}},    {F::OverCurrentCharge, {true, 5.0, 0.5, 0.1}},
      {F::OverTemperature, {true, 60.0, 5.0, 1.0}},         {F::OverTemperatureCharge, {true, 45.0, 5.0, 1.0}},
      {F::UnderTemperatureDischarge, {true, -20.0, 5.0, 1.0}}, {F::UnderTemperatureCharge, {true, 0.0, 5.0, 1.0}},
      {F::BoardOverTemperature, {true, 105.0, 10.0, 1.0}},  {F::PlausibilityCellSum, {true, 0.05, 0.01, 1.0}},
      {F::ThermistorFault, {true, 0.0, 0.0, 1.0}},          {F::CurrentSensorFault, {true, 0.0, 0.0, 0.5}},
      {F::RelayWelded, {true, 0.5, 0.0, 0.2}},              {F::MonitorFault, {true, 0.0, 0.0, 0.0}},
      {F::EStop, {true, 0.0, 0.0, 0.0}},                    {F::CommLoss, {true, 0.0, 0.0, 0.0}},
      {F::PrechargeFailed, {true, 0.0, 0.0, 0.0}},          {F::TemperatureWarning, {false, 51.7, 2.0, 1.0}},
      {F::CellImbalance, {false, 0.05, 0.01, 1.0}},
      {F::FetOverTemperature, {true, 85.0, 10.0, 2.0}},  // added with the FET thermistor (system E)
  };
  ASSERT_EQ(std::size(before), bms::kFaultCount);
  const BmsSettings b;
  for (const auto& e : before) {
    const ProtectionConfig& p = b.protection(e.id);
    SCOPED_TRACE(bms::faultName(e.id));
    EXPECT_EQ(p.enabled, e.p.enabled);
    EXPECT_EQ(p.threshold, e.p.threshold);
    EXPECT_EQ(p.hysteresis, e.p.hysteresis);
    EXPECT_EQ(p.delay_s, e.p.delay_s);
    EXPECT_EQ(p.opens, -1);
  }
}

// A scenario without a protections section flashes the firmware's own table (only the
// info and warning tiers are switched off), so the SI defaults scale back exactly --
// except the charge limit, which comes from the cell (1C of its 2 Ah, hysteresis at most
// 10 % of it: docs/scenario.md "Defaults derived from the pack").
TEST(ProtectionTable, DefaultScenarioFlashesTheFirmwareDefaults) {
  const Scenario s = test::scenarioFromYaml(test::simpleCellYaml(4) + test::kSimpleLoadYaml);
  const bms::Config c = makeBmsConfig(s);
  const bms::Config fw = bms::defaultConfig(4, 2);
  for (uint8_t i = 0; i < bms::kFaultCount; ++i) {
    const bms::ProtectionRule& r = c.rules[i];
    const bms::ProtectionRule& d = fw.rules[i];
    SCOPED_TRACE(bms::faultName(static_cast<F>(i)));
    EXPECT_EQ(r.quantity, d.quantity);
    EXPECT_EQ(r.tripAbove, d.tripAbove);
    const bool charge = static_cast<F>(i) == F::OverCurrentCharge;
    EXPECT_EQ(r.threshold, charge ? 2000 : d.threshold);
    EXPECT_EQ(r.hysteresis, charge ? 200 : d.hysteresis);
    EXPECT_EQ(r.delay_ms, d.delay_ms);
    EXPECT_EQ(r.severity, d.severity);
    EXPECT_EQ(r.latch, d.latch);
    EXPECT_EQ(r.opens, d.opens);
    EXPECT_EQ(r.enabled, d.severity == bms::Severity::Fatal);
  }
  EXPECT_EQ(c.weldCurrent_mA, fw.weldCurrent_mA);
}

// Each row's YAML keys reach its own firmware rule, scaled by its unit; a flag rule has
// no threshold key; an out-of-range threshold names the field and the range.
TEST(ProtectionTable, EachRowsKeysReachItsRule) {
  for (const ProtectionSpec& s : protectionSpecs()) {
    const std::string name = bms::faultName(s.id);
    SCOPED_TRACE(name);
    const std::string head = test::simpleCellYaml(4) + test::kSimpleLoadYaml + "bms:\n  protections:\n    " + name + ": ";
    const auto i = static_cast<size_t>(s.id);
    if (s.use == ThresholdUse::None) {
      const bms::Config c = makeBmsConfig(test::scenarioFromYaml(head + "{delay_ms: 1234, enabled: false}\n"));
      EXPECT_EQ(c.rules[i].delay_ms, 1234u);
      EXPECT_FALSE(c.rules[i].enabled);
      const std::string e = test::yamlErrorOf(head + "{threshold_V: 1}\n");
      EXPECT_NE(e.find("bms.protections." + name + ".threshold_V"), std::string::npos) << e;
      EXPECT_NE(e.find("unknown key"), std::string::npos) << e;
      continue;
    }
    // Three quarters into the range; a current rule's range reaches 100 kA, beyond this
    // pack's current sensor (82.5 A), so 7 A over its minimum instead.
    const double v = std::string(s.unit) != "A" ? s.min + 0.75 * (s.max - s.min) : s.min + 7.0;
    const double h = 0.125 * std::abs(v) + 0.125;
    const std::string th = "threshold_" + std::string(s.unit), hy = "hysteresis_" + std::string(s.unit);
    const bms::Config c = makeBmsConfig(
        test::scenarioFromYaml(head + "{" + th + ": " + fmt(v) + ", " + hy + ": " + fmt(h) + ", delay_ms: 321}\n"));
    EXPECT_EQ(c.rules[i].delay_ms, 321u);
    if (s.use == ThresholdUse::Rule) {
      EXPECT_EQ(c.rules[i].threshold, std::lround(v * s.scale));
      EXPECT_EQ(c.rules[i].hysteresis, std::lround(h * s.scale));
    } else {  // WeldCurrent
      EXPECT_EQ(c.weldCurrent_mA, std::lround(v * s.scale));
    }
    const double bad = s.max + 1.0;
    const std::string e = test::yamlErrorOf(head + "{" + th + ": " + fmt(bad) + "}\n");
    EXPECT_NE(e.find("bms.protections." + name + "." + th), std::string::npos) << e;
    const long line = std::count(head.begin(), head.end(), '\n') + 1;  // where the value sits
    EXPECT_NE(e.find(":" + std::to_string(line) + ":"), std::string::npos) << e;
  }
}

TEST(ProtectionTable, MisspelledProtectionGetsTheClosestName) {
  const std::string e = test::yamlErrorOf(test::simpleCellYaml() + test::kSimpleLoadYaml +
                                          "bms:\n  protections:\n    overtemprature_charge: {threshold_C: 40}\n");
  EXPECT_NE(e.find("did you mean 'overtemperature_charge'"), std::string::npos) << e;
}

// docs/scenario.md lists every protection: a threshold with its SI unit and default
// (and "off" for the tiers that are off by default), a flag rule among the flag rules.
TEST(ProtectionTable, ScenarioDocListsEveryRow) {
  std::ifstream in(test::scenarioDir() + "/../docs/scenario.md");
  std::stringstream ss;
  ss << in.rdbuf();
  std::string doc = std::regex_replace(ss.str(), std::regex("\\s+"), " ");
  doc = std::regex_replace(doc, std::regex("\xE2\x88\x92"), "-");  // U+2212 minus sign
  const size_t list = doc.find("Protections (`unit`, default threshold):");
  const size_t flags = doc.find("flag rules without a threshold", list);
  ASSERT_NE(list, std::string::npos);
  ASSERT_NE(flags, std::string::npos);
  for (const ProtectionSpec& s : protectionSpecs()) {
    const std::string name = bms::faultName(s.id);
    SCOPED_TRACE(name);
    const size_t at = doc.find("`" + name + "` ", list);
    const size_t atFlag = doc.find("`" + name + "`", flags);
    if (s.use == ThresholdUse::None) {
      EXPECT_NE(atFlag, std::string::npos);
      EXPECT_LT(atFlag, doc.find(". ", flags));
      continue;
    }
    ASSERT_LT(at, flags);
    std::smatch m;
    const std::string entry = doc.substr(at + name.size() + 3, 200);
    ASSERT_TRUE(std::regex_search(entry, m, std::regex("^\\(([A-Z])[^,)]*, (-?[0-9.]+)([^)]*)\\)"))) << entry;
    EXPECT_EQ(m[1].str(), s.unit);
    EXPECT_EQ(std::stod(m[2].str()), defaultProtection(s.id).threshold);
    EXPECT_EQ(m[3].str().find("off") != std::string::npos, !defaultProtection(s.id).enabled) << m[3].str();
  }
}

// The event text of every row, against the strings the hand-written switch produced
// before the table (run_tracker.cpp up to issue 15), e.g. from the bundled scenarios; a
// protection without a delay no longer ends in "for 0 ms".
TEST(ProtectionTable, EventTextAsBefore) {
  bms::Telemetry tm{};
  tm.maxCell_mV = 4253;
  tm.minCell_mV = 2498;
  tm.packCurrent_mA = 32999;
  tm.maxTemp_dC = 601;
  tm.minTemp_dC = -150;
  tm.maxDie_dC = 1051;
  auto text = [&](F id, int32_t thr, uint32_t delay) { return protectionDetail(id, thr, delay, tm); };
  EXPECT_EQ(text(F::CellOverVoltage, 4250, 500), "max cell 4.253 V > 4.250 V for 500 ms");
  EXPECT_EQ(text(F::CellUnderVoltage, 2500, 500), "min cell 2.498 V < 2.500 V for 500 ms");
  EXPECT_EQ(text(F::OverCurrentDischarge, 28000, 200), "current 32.999 A > 28.000 A for 200 ms");
  EXPECT_EQ(text(F::OverTemperature, 600, 1000), "max temperature 60.100 C > 60.000 C for 1000 ms");
  EXPECT_EQ(text(F::OverTemperatureCharge, 450, 700), "max temperature while charging 60.100 C > 45.000 C for 700 ms");
  EXPECT_EQ(text(F::UnderTemperatureCharge, 0, 1000), "min temperature while charging -15.000 C < 0.000 C for 1000 ms");
  EXPECT_EQ(text(F::UnderTemperatureDischarge, -100, 600), "min temperature -15.000 C < -10.000 C for 600 ms");
  EXPECT_EQ(text(F::BoardOverTemperature, 1050, 1000), "monitor die 105.100 C > 105.000 C for 1000 ms");
  EXPECT_EQ(text(F::CommLoss, 4, 0), "5 consecutive bad monitor replies");
  EXPECT_EQ(text(F::PlausibilityCellSum, 5, 1000), "sum of cells off the module channel by > 5 mV per cell for 1000 ms");
  EXPECT_EQ(text(F::ThermistorFault, 0, 1000), "thermistor reading at a rail (open or shorted) for 1000 ms");
  EXPECT_EQ(text(F::CurrentSensorFault, 0, 500), "current-sense code at a rail for 500 ms");
  EXPECT_EQ(text(F::EStop, 0, 0), "E-switch pulled");
  EXPECT_EQ(text(F::MonitorFault, 0, 0), "monitor IC protection latched (FAULT line)");
  EXPECT_EQ(text(F::PrechargeFailed, 0, 0), "precharge did not finish in any attempt");
  EXPECT_EQ(text(F::TemperatureWarning, 517, 1000), "max temperature 60.100 C > 51.700 C for 1000 ms");
  EXPECT_EQ(text(F::CellImbalance, 50, 1000), "cell spread 1755 mV > 50 mV for 1000 ms");
  tm.packCurrent_mA = -6;
  EXPECT_EQ(text(F::RelayWelded, 0, 200),
            "relay commanded open but current 0.006 A still flows or its aux contact reads closed for 200 ms");
  tm.packCurrent_mA = -21000;
  EXPECT_EQ(text(F::OverCurrentCharge, 20000, 250), "charge current 21.000 A > 20.000 A for 250 ms");
}

}  // namespace
}  // namespace packsim
