// The thermistor channel table the loader builds once (core/scenario/thermistor_table.hpp):
// the channels in wiring order, each group's nearest cell channel, and the firmware's
// copy in the configuration image. Expectations are worked out by hand from the YAML.
#include <gtest/gtest.h>

#include <string>

#include "core/scenario/monitor_boards.hpp"
#include "core/sim/bms_image.hpp"
#include "core/sim/simulation.hpp"
#include "test_support.hpp"

namespace packsim {
namespace {

// 12 groups, cell thermistors on groups 2 and 10 (1-based), two balancing boards of 6
// cells with two board thermistors each.
std::string twoBoards(const std::string& thermistors) {
  return "name: therm\nseed: 1\n"
         "pack:\n  series: 12\n  initial_soc: 0.5\n"
         "  cell: {capacity_Ah: 3, ocv_V: 3.7, r0_ohm: 0.02, heat_capacity_J_per_K: 40, g_ambient_W_per_K: 0.05}\n"
         "thermal:\n  nodes: [{name: board, heat_capacity_J_per_K: 30, g_ambient_W_per_K: 0.05}]\n"
         "hardware:\n"
         "  afe: {model: bq76pl536a, cells_per_device: 6, thermistors_per_device: 2}\n"
         "  thermistors: " + thermistors + "\n"
         "  balancing: {resistor_ohm: 47, board_node: board, board_thermistors: 2, cells_per_board: 6}\n"
         "load: {current_A: 0}\nrun: {duration_s: 1}\n";
}

TEST(ThermistorTable, TheLoaderWiresTheSitesThenEachBoardsThermistors) {
  const Scenario s = test::scenarioFromYaml(twoBoards("{at_groups: [2, 10]}"));
  const ThermistorTable& t = s.hardware.thermistors;
  ASSERT_EQ(t.count(), 6);
  EXPECT_EQ(t[0].site, ThermSite::Cell);
  EXPECT_EQ(t[0].group, 1);
  EXPECT_EQ(t[1].site, ThermSite::Cell);
  EXPECT_EQ(t[1].group, 9);
  for (int k : {2, 3}) {
    EXPECT_EQ(t[k].site, ThermSite::Board) << k;
    EXPECT_EQ(t[k].board, 0) << k;
    EXPECT_EQ(t[k].group, 0) << k;
  }
  for (int k : {4, 5}) {
    EXPECT_EQ(t[k].board, 1) << k;
    EXPECT_EQ(t[k].group, 6) << k;  // the second board's first cell
  }
  // Groups 1-5 (0-based 0..5) are nearest channel 0; group 6 (0-based 5) is 4 from both
  // and takes the lower channel; from 0-based 6 on channel 1.
  ASSERT_EQ(t.nearest.size(), 12u);
  for (int g = 0; g < 12; ++g) EXPECT_EQ(t.nearest[static_cast<size_t>(g)], g <= 5 ? 0 : 1) << "group " << g;
}

TEST(ThermistorTable, TheFirmwareImageCarriesTheTable) {
  const Scenario s = test::scenarioFromYaml(twoBoards("{at_groups: [2, 10]}"));
  const bms::Config c = makeBmsConfig(s);
  EXPECT_EQ(c.thermistorCount, 6);
  EXPECT_EQ(c.therm.cell, 0b000011u);
  EXPECT_EQ(c.therm.board, 0b111100u);
  EXPECT_EQ(c.therm.fet, 0u);
  EXPECT_EQ(c.therm.perBoard, 2);
  EXPECT_EQ(c.therm.nearest[5], 0);
  EXPECT_EQ(c.therm.nearest[6], 1);
  EXPECT_EQ(c.therm.nearest[12], bms::kMaxThermistors);  // no such group
}

TEST(ThermistorTable, AFetChannelIsNoCellsAndNoGroupsNearest) {
  const Scenario s = loadScenarioFile(test::scenarioDir() + "/faults/e_fet_overheat.yaml");
  const ThermistorTable& t = s.hardware.thermistors;
  ASSERT_EQ(t.count(), 4);
  EXPECT_EQ(t[2].site, ThermSite::Fet);
  EXPECT_EQ(t[2].node, s.hardware.discharge_fet.thermal_node);
  for (int n : t.nearest) EXPECT_NE(n, 2);
  const bms::Config c = makeBmsConfig(s);
  EXPECT_EQ(c.therm.fet, 0b0100u);
  EXPECT_EQ(c.therm.cell, 0b1011u);
}

// Two monitor boards of one device each (the balancing boards are theirs, one board
// thermistor each): board 2's host is flashed with its own table in local numbers.
TEST(ThermistorTable, EachMonitorBoardsHostGetsItsOwnTable) {
  std::string yaml = twoBoards("{at_groups: [2, 10]}");
  yaml.replace(yaml.find("board_thermistors: 2"), 20, "board_thermistors: 1");
  yaml.replace(yaml.find("thermistors_per_device: 2}"), 26, "thermistors_per_device: 2, devices_per_board: 1}");
  const Scenario s = test::scenarioFromYaml(yaml);
  const std::vector<MonitorBoard> boards = monitorBoards(s.hardware, s.pack.series);
  ASSERT_EQ(boards.size(), 2u);
  EXPECT_EQ(boards[0].afeChannels, (std::vector<int>{0, 2}));  // group 2 and board 1's thermistor
  EXPECT_EQ(boards[1].afeChannels, (std::vector<int>{1, 3}));  // group 10 and board 2's
  const ThermistorTable t = boardScenario(s, boards[1]).hardware.thermistors;
  ASSERT_EQ(t.count(), 2);
  EXPECT_EQ(t[0].site, ThermSite::Cell);
  EXPECT_EQ(t[0].group, 3);  // group 10 is the board's fourth
  EXPECT_EQ(t[1].site, ThermSite::Board);
  EXPECT_EQ(t[1].board, 0);
  EXPECT_EQ(t.nearest, (std::vector<int>(6, 0)));
}

}  // namespace
}  // namespace packsim
