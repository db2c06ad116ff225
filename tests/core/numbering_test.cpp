// One numbering (issue 28): cells count 1..series*parallel (fault `cell:`, /truth, the
// summary), series groups 1..series (thermistors `at_groups` / `{group: N}`, channel
// faults `group:`, /measured). The old keys that counted groups under a cell's name are
// refused with the new key named, never reinterpreted.
#include <gtest/gtest.h>

#include "core/sim/simulation.hpp"
#include "core/sim/summary_text.hpp"
#include "test_support.hpp"

namespace packsim {
namespace {

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// A 4s2p pack (cells 1..8, groups 1..4).
std::string pack4s2p() {
  std::string y = test::simpleCellYaml(4);
  y.replace(y.find("  series: 4\n"), 12, "  series: 4\n  parallel: 2\n");
  return y;
}

TEST(Numbering, OldThermistorKeyNamesTheNewOne) {
  std::string y = test::simpleCellYaml(4);
  y.replace(y.find("at_groups"), 9, "at_cells");
  const std::string e = test::yamlErrorOf(y + test::kSimpleLoadYaml);
  EXPECT_TRUE(has(e, "hardware.thermistors.at_cells")) << e;
  EXPECT_TRUE(has(e, "write at_groups: [...] (1..4 series groups, each on its group's first cell)")) << e;
}

TEST(Numbering, ThermistorChannelsCountGroups) {
  std::string y = pack4s2p();
  y.replace(y.find("{at_groups: [1]}"), 16, "{channels: [{cell: 8}]}");
  std::string e = test::yamlErrorOf(y + test::kSimpleLoadYaml);
  EXPECT_TRUE(has(e, "a thermistor channel sits on a series group: write {group: N} (1..4 series groups)")) << e;
  y.replace(y.find("{cell: 8}"), 9, "{group: 5}");
  e = test::yamlErrorOf(y + test::kSimpleLoadYaml);
  EXPECT_TRUE(has(e, "channels[0].group")) << e;
  y.replace(y.find("{group: 5}"), 10, "{group: 4}");
  const Scenario s = test::scenarioFromYaml(y + test::kSimpleLoadYaml);
  ASSERT_EQ(s.hardware.thermistor_sites.size(), 1u);
  EXPECT_EQ(s.hardware.thermistor_sites[0].cell, 3);  // group 4, 0-based
}

// A channel fault acts on a group's measurement channel. Before, `cell: 8` in a 4s2p
// pack was accepted and indexed past the 4 channels (no effect, undefined behaviour).
TEST(Numbering, ChannelFaultsCountGroups) {
  const std::string base = pack4s2p() + test::kSimpleLoadYaml + "faults:\n  - {kind: channel_offset, ";
  std::string e = test::yamlErrorOf(base + "cell: 8, offset_mV: 1000, at_s: 1}\n");
  EXPECT_TRUE(has(e, "faults[0].cell")) << e;
  EXPECT_TRUE(has(e, "write group: N (1..4)")) << e;
  e = test::yamlErrorOf(base + "group: 5, offset_mV: 1000, at_s: 1}\n");
  EXPECT_TRUE(has(e, "faults[0].group")) << e;
  const Scenario s = test::scenarioFromYaml(base + "group: 4, offset_mV: 1000, at_s: 1}\n");
  const RunResult r = runScenario(s);
  EXPECT_GT(test::eventTime(r, "fault_injected", "channel_offset group 4, +1000.0 mV"), 0.0);
  EXPECT_GT(test::eventTime(r, "fault_active", "cell_overvoltage"), 1.0);  // the offset reads +1 V on group 4
}

// A fault's cell counts cells: cell 8 of a 4s2p pack is the second cell of group 4, and
// every line that names it says so; the truth heats cell 8 (index 7), not group 8.
TEST(Numbering, FaultCellsCountCellsAndNameTheirGroup) {
  const Scenario s = test::scenarioFromYaml(pack4s2p() + "load: {current_A: 2}\nrun: {duration_s: 200}\n"
                                            "faults:\n  - {kind: hot_cell, cell: 8, heat_W: 4, at_s: 0}\n");
  const RunResult r = runScenario(s);
  EXPECT_EQ(test::eventTime(r, "fault_injected", "hot_cell cell 8 (group 4), 4 W"), 0.0);
  EXPECT_EQ(r.summary.hottest_cell, 8);
  const std::string text = formatSummary(s, r);
  EXPECT_TRUE(has(text, "C  cell 8 (group 4) at ")) << text;
  const size_t last = r.rec.samples() - 1;
  for (size_t c = 0; c < 7; ++c) EXPECT_LT(r.rec.cell_temp_C[last * 8 + c], r.rec.cell_temp_C[last * 8 + 7]);
}

}  // namespace
}  // namespace packsim
