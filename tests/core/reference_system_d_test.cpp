// Reference system D as its team built it: monitor boards of 6 stacked 6-cell devices,
// each with its own host MCU, the hosts on CAN (the pack host merging the members'
// statuses, the members balancing to the pack's lowest cell), a bad joint that
// silences only the devices above it on its board, a pack skin that reaches 50 °C by
// the end of a race, and the thermistor bias that drains every sixth cell.
#include <gtest/gtest.h>

#include <cmath>

#include "core/scenario/load_scenario.hpp"
#include "core/scenario/monitor_boards.hpp"
#include "core/sim/simulation.hpp"
#include "test_support.hpp"

namespace packsim {
namespace {

Scenario preset(const std::string& rel) { return loadScenarioFile(test::scenarioDir() + "/" + rel); }

TEST(ReferenceSystemD, FourBoardsOfSixDevicesEachWithItsThermistors) {
  const Scenario s = preset("motorcycle_110s.yaml");
  const std::vector<MonitorBoard> b = monitorBoards(s.hardware, s.pack.series);
  ASSERT_EQ(b.size(), 4u);
  const int cells[4] = {36, 36, 36, 2}, devices[4] = {6, 6, 6, 1}, therms[4] = {10, 10, 10, 0};
  for (size_t k = 0; k < 4; ++k) {
    EXPECT_EQ(b[k].cells, cells[k]);
    EXPECT_EQ(b[k].devices, devices[k]);
    EXPECT_EQ(b[k].afeChannels.size(), static_cast<size_t>(therms[k]));
    EXPECT_TRUE(b[k].mcuChannels.empty());
    for (int ch : b[k].afeChannels) {  // each on a cell of its own board
      const int cell = s.hardware.thermistor_sites[static_cast<size_t>(ch)].cell;
      EXPECT_GE(cell, b[k].firstCell);
      EXPECT_LT(cell, b[k].firstCell + b[k].cells);
    }
  }
  // A member board has no ADC of its own: more thermistors than inputs is an error.
  const std::string e = test::yamlErrorOf(
      "name: x\npack: {series: 12, cell: {capacity_Ah: 5, ocv_V: 3.7, r0_ohm: 0.01}}\n"
      "hardware:\n  afe: {model: bq76pl536a, cells_per_device: 6, devices_per_board: 1}\n"
      "  thermistors: {at_groups: [1, 2, 7, 8, 9]}\nload: {current_A: 1}\nrun: {duration_s: 1}\n");
  EXPECT_NE(e.find("devices_per_board: monitor board 2 (cells 7-12) has more thermistors than its 1 devices have inputs (2)"),
            std::string::npos)
      << e;
}

// Two boards of one 6-cell device; the second board's host is a member on CAN.
std::string twoBoards(const std::string& extra) {
  return "name: two_boards\nseed: 3\npack: {series: 12, initial_soc: 0.6, cell: {capacity_Ah: 20, ocv_V: {poly: [0.8, 3.3]}, r0_ohm: 0.002}}\n"
         "hardware:\n  afe: {model: bq76pl536a, cells_per_device: 6, devices_per_board: 1, fault_line_opens_relay: false}\n"
         "  cell_adc: {noise_mV_rms: 0}\n  thermistors: {at_groups: [2, 8]}\n"
         "bms:\n  tick_ms: 10\n  readout: {period_ms: 1000}\n  comm_loss_count: 2\n"
         "load: {current_A: 5}\nrun: {duration_s: 8, stop_after_trip_s: 1}\noutput: {interval_s: 0.01}\n" + extra;
}

// A member's cell over its limit reaches the pack host over CAN: the member reads it at
// its read-out (2 s), sends its status after it, the pack host merges it at its next
// control tick; the debounce (500 ms) runs there.
TEST(ReferenceSystemD, AMembersCellTripsThePackHostOverCan) {
  const RunResult r = runScenario(test::scenarioFromYaml(twoBoards(
      "faults: [{kind: channel_offset, group: 9, offset_mV: 1000, at_s: 2}]\n")));
  const double seen = test::eventTime(r, "fault_active", "cell_overvoltage");
  EXPECT_NEAR(seen, 2.0 + 0.5 + 0.01, 0.0101) << "read-out at 2.0, CAN at 2.01, debounce 0.5 s";
  EXPECT_EQ(r.summary.trip_reason, "cell_overvoltage");
  // The measured cell 9 (the member's third) is where the record puts it.
  const size_t k = test::sampleAt(r.rec, 2.5);
  EXPECT_GT(r.rec.meas_cell_voltage_mV[k * 12 + 8], 4000);
  EXPECT_LT(r.rec.meas_cell_voltage_mV[k * 12 + 7], 3800);
}

// A member's MCU that hangs stops sending its status: its last arrived at 1.01 s (after
// its 1.0 s read-out); each read-out period without one is a bad read of that board, so
// the pack host calls comm loss at the 2nd missed period, 3.01 s.
TEST(ReferenceSystemD, ASilentMemberIsACommLossAtThePackHost) {
  const RunResult r = runScenario(test::scenarioFromYaml(twoBoards("faults: [{kind: host_dead, board: 2, at_s: 2}]\n")));
  EXPECT_NEAR(test::eventTime(r, "fault_active", "comm_loss"), 3.01, 1e-6);
  EXPECT_EQ(r.summary.trip_reason, "comm_loss");
  EXPECT_NE(test::yamlErrorOf(twoBoards("faults: [{kind: host_dead, board: 3, at_s: 2}]\n")).find("board"),
            std::string::npos);
}

// A bad joint above device 9 (board 2's third): devices 10-12 read 0xFF, every other
// device of every board answers.
TEST(ReferenceSystemD, ABadJointSilencesOnlyTheDevicesAboveItOnItsBoard) {
  Scenario s = preset("faults/d_broken_link.yaml");
  s.run.duration_s = 602.0;
  s.output.interval_s = 0.01;
  const RunResult r = runScenario(s);
  const size_t k = test::sampleAt(r.rec, 601.0);
  const int devices = r.rec.devices;
  ASSERT_EQ(devices, 19);
  for (int d = 0; d < devices; ++d)
    EXPECT_EQ(r.rec.comm_bad[k * static_cast<size_t>(devices) + static_cast<size_t>(d)] > 0, d >= 9 && d <= 11)
        << "device " << d + 1;
  // Board 2 reports each read-out over CAN, its bad ones too: the pack host trips on
  // the report after the 2nd bad one (the read-out holds board 2's host ~25 ms, then its
  // status goes out; the pack host acts at its next tick). A member that reported only
  // read-outs with new cells left the pack host to trip on the silence, at 601.03 s.
  EXPECT_NEAR(test::eventTime(r, "fault_active", "comm_loss"), 601.05, 1e-6);
}

// Balancing across boards: board 2's 36 cells sit 1 Ah above the rest, uniform among
// themselves. Its host bleeds them to the pack's lowest, which the pack host shares on
// CAN: each loses V/R over the time it balances (47 ohm at ~3.84 V: 81.7 mA, from the
// end of the 600 s rest and the first 16-reading block), the other boards' cells nothing.
TEST(ReferenceSystemD, AHighMemberBoardBleedsToThePacksLowestCell) {
  Scenario s = preset("balance/motorcycle_110s_balancing.yaml");
  s.hardware.afe.thermistor_bias_A = 0.0;  // only the balancing moves charge here
  s.run.solver = RunConfig::Solver::Fast;
  const RunResult r = runScenario(s);
  const Recording& rec = r.rec;
  const size_t last = rec.samples() - 1;
  const double cap_Ah = s.pack.cell.capacity_Ah;
  const double balancing_s = s.run.duration_s - s.bms.image.balance.rest_ms * 1e-3 - 16.0;
  const double expected_Ah = 3.84 / 47.0 * balancing_s / 3600.0;
  for (int c = 0; c < 110; ++c) {
    const double lost_Ah = (rec.cell_soc[static_cast<size_t>(c)] - rec.cell_soc[last * 110 + static_cast<size_t>(c)]) * cap_Ah;
    if (c >= 36 && c < 72)
      EXPECT_NEAR(lost_Ah, expected_Ah, 0.04 * expected_Ah) << "cell " << c + 1;
    else
      EXPECT_LT(lost_Ah, 1e-3) << "cell " << c + 1;
  }
}

// The pack skin by the end of the 20-minute race: the 50 C+ the team saw.
TEST(ReferenceSystemD, ThePackSkinReachesFiftyDegreesByTheEndOfARace) {
  const Scenario s = preset("motorcycle_110s.yaml");
  SimulationRun run(s);
  while (run.step()) {
  }
  const Plant& p = run.plant();
  const int skin = p.thermal().find("pack_skin");
  ASSERT_GE(skin, 0);
  const double skin_C = run.state()[p.tempIndex(skin)];
  EXPECT_GT(skin_C, 50.0);
  EXPECT_LT(skin_C, 56.0);
  run.finish();
}

// Parked for a week with the BMS on: every device's 2.5 mA thermistor bias from its top
// cell takes 2.5 mA x 604800 s / 40 Ah = 1.05 % of SOC more from cells 6, 12, ... 108,
// 110 than from the cells beside them (the scenario's 1 % capacity spread left out).
TEST(ReferenceSystemD, TheThermistorBiasDrainsEverySixthCellWhileParked) {
  Scenario s = preset("balance/motorcycle_110s_parked_week.yaml");
  s.pack.spread.capacity_rel_sd = 0.0;  // every cell 40 Ah: the same charge is the same SOC
  const RunResult r = runScenario(s);
  const Recording& rec = r.rec;
  const size_t last = rec.samples() - 1;
  auto drop = [&](int cell) {
    const size_t c = static_cast<size_t>(cell - 1);
    return rec.cell_soc[c] - rec.cell_soc[last * 110 + c];
  };
  const double expected = 0.0025 * 604800.0 / (40.0 * 3600.0);
  for (int top : {6, 12, 54, 108, 110}) EXPECT_NEAR(drop(top) - drop(top - 1), expected, 0.01 * expected) << top;
  EXPECT_NEAR(drop(7) - drop(5), 0.0, 1e-4);
}

}  // namespace
}  // namespace packsim
