// A library firmware in a whole run (bms.firmware): the scenario section and its
// blob, a firmware that crashes or hangs while the relay is closed (the monitor's own
// COV comparator and FAULT line still open it, at the datasheet threshold and delay),
// and the example firmware judged by `packsim check` on its fault subset.
#include <gtest/gtest.h>

#include <cstdlib>

#include "core/sim/simulation.hpp"
#include "core/sim/summary_text.hpp"
#include "test_support.hpp"

namespace packsim {
namespace {

// System C's bench pack on charge from full with the probe firmware in `mode`
// (tests/firmware/probe_fw.c): it closes the relay at init, then fails at 50 ms.
std::string chargingBench(int mode) {
  return std::string("extends: bench_6s_ncr18650_2C.yaml\n") +
         "bms: {tick_ms: 10, firmware: {library: " PACKSIM_PROBE_FW ", watchdog_ms: 200, config: {mode: " +
         std::to_string(mode) + ", at_ms: 50}}}\n" +
         "hardware: {afe: {secondary: {cov_V: 4.30, cov_delay_ms: 500}}}\n"
         "load: {current_A: -3.0}\n"
         "run: {duration_s: 900}\n"
         "output: {interval_s: 0.01}\n";
}

void expectHardwareStillProtects(int mode, const std::string& cause) {
  const Scenario s = test::scenarioFromYaml(chargingBench(mode));
  const RunResult r = runScenario(s);
  const double dead_s = test::eventTime(r, "firmware_fault", cause);
  ASSERT_GE(dead_s, 0.0) << cause;
  EXPECT_NEAR(dead_s, 0.05, 1e-9);
  EXPECT_NE(r.summary.firmware_status.find("firmware_fault at 0.050 s: " + cause), std::string::npos)
      << r.summary.firmware_status;
  // The dead MCU holds the relay closed; the charge goes on until a cell crosses the
  // comparator's 4.30 V, which after its 0.5 s delay latches FAULT and opens the relay.
  const double opened_s = test::eventTime(r, "relay_contact", "opened");
  const double fault_s = test::eventTime(r, "monitor_fault_line", "asserted");
  ASSERT_GT(fault_s, dead_s);
  ASSERT_GE(opened_s, fault_s);
  double over_s = -1.0;  // first recorded sample with a cell above the threshold
  for (size_t i = 0; i < r.rec.time_s.size() && over_s < 0.0; ++i)
    for (int c = 0; c < r.rec.cells; ++c)
      if (r.rec.cell_voltage_V[i * static_cast<size_t>(r.rec.cells) + static_cast<size_t>(c)] > 4.30) over_s = r.rec.time_s[i];
  ASSERT_GE(over_s, 0.0);
  EXPECT_NEAR(fault_s, over_s + 0.5, 0.011);  // the delay, to within the 10 ms tick
  EXPECT_FALSE(r.summary.tripped);  // the firmware never reported a trip
}

TEST(FirmwareRun, ACrashedFirmwareLeavesTheHardwareProtectionActing) {
  expectHardwareStillProtects(2, "crash in task 0 (period 10 ms): SIGSEGV");
}

TEST(FirmwareRun, AHungFirmwareLeavesTheHardwareProtectionActing) {
  expectHardwareStillProtects(3, "hang in task 0 (period 10 ms)");
}

// The outputs act at the instant the firmware wrote them, not at the tick: the probe
// (PIN_TIMING) closes the relay at init after one 12-byte SPI transaction and opens it in
// its 50 ms task after two. At 250 kHz a transaction is 12 · 8 / 250e3 = 384 us, so the
// contact closes at 0.384 ms and opens at 50.768 ms; the 5.9 A load flows for 50.384 ms
// between them (at the ticks it would have flowed 50 ms: 0 to 50 ms).
TEST(FirmwareRun, OutputsActAtTheInstantTheFirmwareWroteThem) {
  const Scenario s = test::scenarioFromYaml(
      "extends: bench_6s_ncr18650_2C.yaml\n"
      "hardware: {afe: {baud: 250000}}\n"
      "bms: {tick_ms: 10, firmware: {library: " PACKSIM_PROBE_FW ", config: {mode: 13, at_ms: 50}}}\n"
      "run: {duration_s: 0.2}\n");
  const RunResult r = runScenario(s);
  const double transfer_s = 12 * 8 / 250e3;
  EXPECT_NEAR(test::eventTime(r, "relay_contact", "closed"), transfer_s, 1e-9);
  EXPECT_NEAR(test::eventTime(r, "relay_contact", "opened"), 0.050 + 2 * transfer_s, 1e-9);
  EXPECT_NEAR(r.summary.charge_delivered_Ah, 5.9 * (0.050 + transfer_s) / 3600.0, 1e-6 * 5.9 * 0.05 / 3600.0);
}

TEST(FirmwareRun, TheConfigMapBecomesLittleEndianInt32InFileOrder) {
  const Scenario s = test::scenarioFromYaml(
      "extends: bench_6s_ncr18650_2C.yaml\n"
      "bms: {firmware: {library: " PACKSIM_PROBE_FW ", config: {b: 1, a: [2, -3], c: 0x10}}}\n");
  const std::vector<uint8_t> expected = {1, 0, 0, 0, 2, 0, 0, 0, 0xFD, 0xFF, 0xFF, 0xFF, 0x10, 0, 0, 0};
  EXPECT_EQ(s.bms.firmware.config, expected);
  EXPECT_TRUE(s.bms.firmware.library);
}

TEST(FirmwareRun, BadFirmwareSectionsAreScenarioErrors) {
  const std::string base = "extends: bench_6s_ncr18650_2C.yaml\n";
  const std::string notInt = test::yamlErrorOf(base + "bms: {firmware: {library: " PACKSIM_PROBE_FW
                                                      ", config: {gain: 1.5}}}\n");
  EXPECT_NE(notInt.find("test.yaml:2:"), std::string::npos) << notInt;
  EXPECT_NE(notInt.find("bms.firmware.config.gain"), std::string::npos) << notInt;
  EXPECT_NE(notInt.find("expected an integer"), std::string::npos) << notInt;
  const std::string tooBig = test::yamlErrorOf(base + "bms: {firmware: {library: " PACKSIM_PROBE_FW
                                                      ", config: {x: [1, 4294967296]}}}\n");
  EXPECT_NE(tooBig.find("bms.firmware.config.x[1]"), std::string::npos) << tooBig;
  const std::string missing = test::yamlErrorOf(base + "bms: {firmware: {library: no_such_fw}}\n");
  EXPECT_NE(missing.find("firmware library 'no_such_fw' not found; tried:"), std::string::npos) << missing;
  EXPECT_NE(missing.find("libno_such_fw.so"), std::string::npos) << missing;
  const std::string typo = test::yamlErrorOf(base + "bms: {firmware: {library: " PACKSIM_PROBE_FW
                                                    ", confg: {a: 1}}}\n");
  EXPECT_NE(typo.find("config"), std::string::npos) << typo;
}

// A library firmware's trip event is the run's trip (trip_reason, trip time).
TEST(FirmwareRun, ATripEventIsTheSummarysTrip) {
  const Scenario s = test::scenarioFromYaml(
      "extends: bench_6s_ncr18650_2C.yaml\n"
      "bms: {tick_ms: 10, firmware: {library: " PACKSIM_PROBE_FW ", config: {mode: 10, at_ms: 1500}}}\n"
      "run: {duration_s: 5, stop_after_trip_s: 1}\n");
  const RunResult r = runScenario(s);
  ASSERT_TRUE(r.summary.tripped);
  EXPECT_EQ(r.summary.trip_reason, "overcurrent_discharge");
  EXPECT_NEAR(r.summary.trip_time_s, 1.5, 1e-9);
  EXPECT_NEAR(r.summary.duration_s, 2.5, 0.011);  // stop_after_trip_s after it
  EXPECT_NE(r.summary.firmware_status.find("ran to the end"), std::string::npos);
}

// The example firmware on system C: discharge to its own under-voltage trip, and the
// fault subset (over-current, hot cell, E-switch, silent device), each judged by its
// expect block through the command line as a user runs it.
TEST(FirmwareRun, TheExampleFirmwarePassesItsScenariosUnderPacksimCheck) {
  // Host mode's; target mode's (firmware/target/, the ELFs) are target_mode_test's and the bundled scenarios'.
  const std::string cmd = std::string(PACKSIM_BINARY) + " check " + test::scenarioDir() + "/firmware/*.yaml > /dev/null";
  EXPECT_EQ(std::system(cmd.c_str()), 0) << cmd;
}

// A firmware whose bus writes the part ignores (the probe's BUS mode sends the bytes
// 1 2 3 4 every 10 ms: on a BQ76PL536A stack a write of 0x03 to register 0x02 at
// address 0 with a CRC byte that is not the frame's): the part rejects it, as before,
// and the run says so -- one register_misuse event naming the part, device, register
// and reason, with the count of frames, which is the count of the firmware's own
// "bus ..." reports of its transfers.
TEST(FirmwareRun, WritesThePartIgnoresBecomeOneRegisterMisuseEventWithTheirCount) {
  const Scenario s = test::scenarioFromYaml(
      "extends: bench_6s_ncr18650_2C.yaml\n"
      "bms: {tick_ms: 10, firmware: {library: " PACKSIM_PROBE_FW ", config: {mode: 1, at_ms: 50}}}\n"
      "load: {current_A: 1.0}\nrun: {duration_s: 2}\n");
  const RunResult r = runScenario(s);
  long transfers = 0;
  double firstTransfer_s = -1.0;
  std::vector<const Event*> misuse;
  for (const Event& e : r.events) {
    if (e.detail.rfind("bus ", 0) == 0) {
      ++transfers;
      if (firstTransfer_s < 0.0) firstTransfer_s = e.time_s;
    }
    if (e.kind == "register_misuse") misuse.push_back(&e);
  }
  ASSERT_GT(transfers, 100);
  ASSERT_EQ(misuse.size(), 1u);
  EXPECT_EQ(misuse[0]->detail.rfind("bq76pl536a device 1: GPAI: write with a bad CRC", 0), 0u) << misuse[0]->detail;
  EXPECT_NE(misuse[0]->detail.find("; " + std::to_string(transfers) + " times"), std::string::npos) << misuse[0]->detail;
  EXPECT_NEAR(misuse[0]->time_s, firstTransfer_s, 0.01);
  // The summary shows it.
  EXPECT_NE(formatSummary(s, r).find("bus misuse"), std::string::npos);
}

}  // namespace
}  // namespace packsim
