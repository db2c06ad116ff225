// The monitor inputs a firmware never read (core/sim/read_coverage.hpp): the example C
// firmware told `cell_count: 6` on a 12s pack of two BQ76PL536A devices reads only the
// first device, and the run names the other's six series groups and its thermistors;
// told 12, nothing. packsim's own core reads every cell and thermistor on each part,
// one board or several; a device silent from the start is never heard, so never read.
#include <gtest/gtest.h>

#include <algorithm>

#include "core/check/check.hpp"
#include "core/sim/simulation.hpp"
#include "core/sim/summary_text.hpp"
#include "models/afe/monitor_part.hpp"
#include "test_support.hpp"

namespace packsim {
namespace {

std::vector<std::string> unread(const RunResult& r) {
  std::vector<std::string> out;
  for (const Event& e : r.events)
    if (e.kind == "monitor_unread") out.push_back(e.detail);
  return out;
}

// The words wholly inside [first, first + count), one by one.
TEST(ReadCoverage, WordsCoveredIsTheRegistersAReadDeliversWhole) {
  for (size_t base : {size_t{0}, size_t{3}, size_t{0x14}})
    for (size_t n : {size_t{1}, size_t{2}, size_t{6}, size_t{16}})
      for (size_t first = 0; first < 60; ++first)
        for (size_t count = 0; count < 60; ++count) {
          uint32_t want = 0;
          for (size_t i = 0; i < n; ++i)
            if (base + 2 * i >= first && base + 2 * i + 2 <= first + count) want |= 1u << i;
          ASSERT_EQ(wordsCovered(first, count, base, n), want) << base << " " << n << " " << first << " " << count;
        }
}

TEST(ReadCoverage, RegisterSpanIsTheRegistersBelow64AReadCovers) {
  for (size_t first = 0; first < 100; ++first)
    for (size_t count = 0; count < 100; ++count) {
      uint64_t want = 0;
      for (size_t r = first; r < first + count && r < 64; ++r) want |= uint64_t{1} << r;
      ASSERT_EQ(registerSpan(first, count), want) << first << " " << count;
    }
}

// 12 series groups on two BQ76PL536A devices of six; thermistors at groups 1, 2 (the
// first device's two inputs) and 7, 8 (the second's); the example firmware reads
// `cells` of them.
std::string examplePack(int cells) {
  return "extends: bench_6s_ncr18650_2C.yaml\n"
         "pack: {series: 12}\n"
         "hardware: {afe: {model: bq76pl536a, cells_per_device: 6, devices: 2}, thermistors: {at_groups: [1, 2, 7, 8]}}\n"
         "thermal: {cell_to_cell_W_per_K: 1.0}\n"  // every cell within reach of a thermistor: no warning
         "load: {current_A: 1}\n"
         "run: {duration_s: 3}\n"
         "bms: {tick_ms: 10, firmware: {library: packsim_example_bms, config: {cell_count: " +
         std::to_string(cells) +
         ", cells_per_device: 6, capacity_mAh: 3100, ocd_mA: 20000,"
         " ocv_mV: [2600, 3240, 3435, 3515, 3569, 3622, 3702, 3846, 3953, 4057, 4180]}}}\n";
}

TEST(ReadCoverage, AFirmwareToldSixCellsOnATwelveCellStackLeavesTheSecondDeviceUnread) {
  const RunResult r = runScenario(test::scenarioFromYaml(examplePack(6)));
  const std::vector<std::string> notes = unread(r);
  ASSERT_EQ(notes.size(), 2u) << testing::PrintToString(notes);
  EXPECT_EQ(r.summary.unmonitored_groups, 6);  // /summary, summary.csv, Python's r.summary
  EXPECT_EQ(notes[0],
            "series groups 7-12 of 12 (on bq76pl536a device 2 of 2): the firmware never read their cell voltage in the "
            "run's 3.00 s; the BMS could not see them");
  EXPECT_EQ(notes[1], "thermistor channels 3-4 (at groups 7, 8; on bq76pl536a device 2 of 2): the firmware never read "
                      "them in the run's 3.00 s");
  const Scenario s = test::scenarioFromYaml(examplePack(6));
  const std::string text = formatSummary(s, r);
  EXPECT_NE(text.find("unmonitored     " + notes[0]), std::string::npos) << text;
  EXPECT_NE(text.find("unmonitored     " + notes[1]), std::string::npos) << text;
  // `check` passes the scenario on its expect: block, and says so under the verdict.
  const CheckOutcome c = judge(s, r);
  for (const std::string& n : notes)
    EXPECT_NE(std::find(c.warnings.begin(), c.warnings.end(), n), c.warnings.end()) << n;
}

TEST(ReadCoverage, TheSameFirmwareToldTwelveCellsReadsThemAll) {
  const RunResult r = runScenario(test::scenarioFromYaml(examplePack(12)));
  EXPECT_TRUE(unread(r).empty()) << testing::PrintToString(unread(r));
  EXPECT_EQ(r.summary.unmonitored_groups, 0);
  EXPECT_EQ(formatSummary(test::scenarioFromYaml(examplePack(12)), r).find("unmonitored"), std::string::npos);
  EXPECT_TRUE(judge(test::scenarioFromYaml(examplePack(12)), r).warnings.empty());
}

// The example firmware told 8 cells on 4-cell devices, on a stack of two 6-cell devices:
// its ADC_CONTROL (CELL_SEL) converts each device's first 4 cells, and it reads the whole
// result block, VCELL5-6 included, whose registers never hold a conversion. Reading them
// counted as reading those cells, and no line said that groups 5-6 and 11-12 were never
// measured; now a register counts once it holds a conversion of its input.
TEST(ReadCoverage, CellsTheDeviceNeverConvertedAreUnreadThoughTheirRegistersWereRead) {
  std::string yaml = examplePack(8);
  yaml.replace(yaml.find("cells_per_device: 6, capacity"), 19, "cells_per_device: 4");
  const RunResult r = runScenario(test::scenarioFromYaml(yaml));
  const std::vector<std::string> notes = unread(r);
  ASSERT_EQ(notes.size(), 1u) << testing::PrintToString(notes);
  EXPECT_EQ(notes[0], "series groups 5-6, 11-12 of 12 (on bq76pl536a devices 1-2 of 2): the firmware never read their "
                      "cell voltage in the run's 3.00 s; the BMS could not see them");
  EXPECT_EQ(r.summary.unmonitored_groups, 4);
}

// A fifth thermistor, at group 10, goes to the MCU's own ADC (the two devices take two
// each). The example firmware reads none of the MCU's thermistor inputs; packsim's core
// reads each every tick.
TEST(ReadCoverage, AThermistorOnTheMcusAdcThatTheFirmwareNeverReadIsNamed) {
  std::string yaml = examplePack(12);
  yaml.replace(yaml.find("at_groups: [1, 2, 7, 8]"), 23, "at_groups: [1, 2, 7, 8, 10]");
  const RunResult r = runScenario(test::scenarioFromYaml(yaml));
  const std::vector<std::string> notes = unread(r);
  ASSERT_EQ(notes.size(), 1u) << testing::PrintToString(notes);
  EXPECT_EQ(notes[0], "thermistor channel 5 (at group 10; on the MCU's own ADC, channel 16 from PSFW_ADC_THERMISTOR0 = "
                      "16): the firmware never read it in the run's 3.00 s");
  EXPECT_EQ(r.summary.unmonitored_groups, 0);  // every cell was read
  const std::string core = yaml.substr(0, yaml.find("bms: {")) + "bms: {tick_ms: 10}\n";  // no firmware: the core
  const RunResult own = runScenario(test::scenarioFromYaml(core));
  EXPECT_TRUE(unread(own).empty()) << testing::PrintToString(unread(own));
}

// Each part packsim's core drives, on its bundled pack (one board, or D's six), reads
// every cell and thermistor within two seconds.
TEST(ReadCoverage, PacksimsCoreReadsEveryInputOnEveryPart) {
  for (const char* name : {"bench_6s_ncr18650_2C.yaml", "eco_marathon_12s.yaml", "formula_student_96s.yaml",
                           "scooter_16s_lto.yaml", "motorcycle_110s.yaml"}) {
    const RunResult r =
        runScenario(test::scenarioFromYaml(std::string("extends: ") + name + "\nrun: {duration_s: 2}\n"));
    EXPECT_TRUE(unread(r).empty()) << name << ": " << testing::PrintToString(unread(r));
  }
  const RunResult r = runScenario(test::scenarioFromYaml(
      "extends: formula_student_96s.yaml\nhardware: {afe: {model: ltc6811, cells_per_device: 12, thermistors_per_device: 5}}\n"
      "pack: {series: 96}\nrun: {duration_s: 2}\n"));
  EXPECT_TRUE(unread(r).empty()) << "ltc6811: " << testing::PrintToString(unread(r));
}

TEST(ReadCoverage, ADeviceSilentFromTheStartIsNeverRead) {
  const RunResult r = runScenario(test::scenarioFromYaml(
      "extends: bench_6s_ncr18650_2C.yaml\n"
      "pack: {series: 12}\n"
      "hardware: {afe: {model: bq76pl536a, cells_per_device: 6, devices: 2}, thermistors: {at_groups: [1, 7]}}\n"
      "faults: [{kind: device_silent, device: 2, at_s: 0}]\n"
      "run: {duration_s: 2}\n"));
  const std::vector<std::string> notes = unread(r);
  ASSERT_FALSE(notes.empty());
  EXPECT_EQ(notes[0].rfind("series groups 7-12 of 12 (on bq76pl536a device 2 of 2)", 0), 0u) << notes[0];
}

}  // namespace
}  // namespace packsim
