// A library firmware in a whole run (bms.firmware): the scenario section and its
// blob, a firmware that crashes or hangs while the relay is closed (the monitor's own
// COV comparator and FAULT line still open it, at the datasheet threshold and delay),
// and the example firmware judged by `packsim check` on its fault subset.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>

#include "core/check/check.hpp"
#include "core/text_fmt.hpp"
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
  // The relay commands are the firmware's writes, at their instants (they were logged at
  // the ticks, 0 and 50 ms: a command before the firmware had decided it).
  EXPECT_NEAR(test::eventTime(r, "relay", "close"), transfer_s, 1e-9);
  EXPECT_NEAR(test::eventTime(r, "relay", "open"), 0.050 + 2 * transfer_s, 1e-9);
  EXPECT_EQ(test::eventsOf(r, "relay").size(), 2u);
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
  // The summary shows it, and `packsim check` warns of it (a passing check said nothing).
  EXPECT_NE(formatSummary(s, r).find("bus misuse"), std::string::npos);
  const std::vector<std::string> warnings = judge(s, r).warnings;
  EXPECT_NE(std::find(warnings.begin(), warnings.end(), "bus misuse from " + fmt("%.4f s: ", misuse[0]->time_s) + misuse[0]->detail),
            warnings.end());
}

// The summary of a user's firmware's run has no line about estimates only packsim's core
// makes: "capacity (SOH) no estimate (needs two rests ...)" and "SOC display up to 0 bars
// below and 0 above" judged a core that did not run, and the balancing line said "the
// firmware never reported balancing" of a firmware that has no way to. The core's run of
// the same pack still has them.
TEST(FirmwareRun, AUserFirmwaresSummaryHasNoLinesOfTheCoresEstimates) {
  const std::string pack = "hardware: {balancing: {resistor_ohm: 47}}\nrun: {duration_s: 2}\n";
  const Scenario user = test::scenarioFromYaml("extends: firmware/c_example_firmware.yaml\n" + pack);
  const std::string text = formatSummary(user, runScenario(user));
  EXPECT_EQ(text.find("capacity (SOH)"), std::string::npos) << text;
  EXPECT_EQ(text.find("SOC display"), std::string::npos) << text;
  EXPECT_NE(text.find("balancing       the firmware set no balancing switch; bled 0.000 Ah"), std::string::npos) << text;
  const Scenario core = test::scenarioFromYaml("extends: bench_6s_ncr18650_2C.yaml\n" + pack);
  const std::string coreText = formatSummary(core, runScenario(core));
  EXPECT_NE(coreText.find("capacity (SOH)"), std::string::npos) << coreText;
  EXPECT_NE(coreText.find("SOC display"), std::string::npos) << coreText;
}

// packsim's core's protection settings do not bind a user's firmware: its scenario on a
// sensitive current sensor (5 mOhm x 20: +/-16.5 A) loads, where the core's default 30 A
// over-current threshold is an error for the core (and "state the threshold" warnings
// for keys the user's firmware never reads are not given).
TEST(FirmwareRun, TheCoresProtectionDefaultsDoNotBindAUserFirmware) {
  const std::string pack = "pack: {series: 4, cell: {preset: ncr18650_3p1Ah}}\n"
                           "hardware: {afe: {model: bq76pl536a, cells_per_device: 4}, current_sense: {shunt_ohm: 0.005, "
                           "amp_gain: 20}}\nload: {current_A: 1}\nrun: {duration_s: 1}\n";
  const std::string core = test::yamlErrorOf(pack);
  EXPECT_NE(core.find("over-current threshold 30 A is beyond the current sensor's range"), std::string::npos) << core;
  const Scenario user = test::scenarioFromYaml(pack + "bms: {tick_ms: 10, firmware: {library: " PACKSIM_PROBE_FW
                                                      ", config: {mode: 0, at_ms: 0}}}\n");
  for (const std::string& w : user.warnings) EXPECT_EQ(w.find("bms.protections"), std::string::npos) << w;
  // Nor bms.balancing's: balancing resistors without a board node leave no board
  // temperature to any firmware, said without the core's key.
  std::string balanced = pack;
  balanced.replace(balanced.find("current_sense"), 0, "balancing: {resistor_ohm: 47}, ");
  const Scenario board = test::scenarioFromYaml(balanced + "bms: {tick_ms: 10, firmware: {library: " PACKSIM_PROBE_FW
                                                           ", config: {mode: 0, at_ms: 0}}}\n");
  ASSERT_FALSE(board.warnings.empty());
  for (const std::string& w : board.warnings) EXPECT_EQ(w.find("bms.balancing"), std::string::npos) << w;
  EXPECT_NE(board.warnings.back().find("no board-temperature limit of the firmware can act"), std::string::npos)
      << board.warnings.back();
}

// A firmware that reads an ADC channel the board does not have (the probe's WIRING mode
// reads channels 17 and 18 every 10 ms; system C's bench gives the MCU no thermistors)
// gets PSFW_NO_CHANNEL, and the run says so: one firmware_misuse event per channel at its
// first read, a `board misuse` summary line each, and `packsim check` warns.
TEST(FirmwareRun, AChannelTheBoardDoesNotHaveIsInTheSummaryAndCheck) {
  const Scenario s = test::scenarioFromYaml(
      "extends: bench_6s_ncr18650_2C.yaml\n"
      "bms: {tick_ms: 10, firmware: {library: " PACKSIM_PROBE_FW ", config: {mode: 17, at_ms: 0}}}\n"
      "run: {duration_s: 1}\n");
  const RunResult r = runScenario(s);
  const std::vector<const Event*> misuse = test::eventsOf(r, "firmware_misuse");
  ASSERT_EQ(misuse.size(), 5u);  // ADC 17, 18, input 9, output 7, DAC 3
  EXPECT_EQ(misuse[0]->detail.rfind("adc_read(channel 17): the board has no such ADC channel (it has 0 current sense, "
                                    "1 bus voltage); it returned PSFW_NO_CHANNEL (-3)",
                                    0),
            0u)
      << misuse[0]->detail;
  EXPECT_DOUBLE_EQ(misuse[0]->time_s, 0.010);
  const std::string summary = formatSummary(s, r);
  EXPECT_NE(summary.find("board misuse    0.0100 s  adc_read(channel 18)"), std::string::npos) << summary;
  std::vector<std::string> said;  // check's warnings of them (beside the probe's 15 ms task and unread cells)
  for (const std::string& w : judge(s, r).warnings)
    if (w.rfind("the firmware at ", 0) == 0) said.push_back(w);
  ASSERT_EQ(said.size(), 5u);
  EXPECT_EQ(said[0].rfind("the firmware at 0.0100 s: adc_read(channel 17)", 0), 0u) << said[0];
}

// The events of packsim's core's own state (its RAM, read by the debug probe) belong to
// a run of the core: a user's firmware keeps its state where packsim cannot see it, so
// its run has no `bms_state init` or `balancing disabled` at t = 0 (which named states it
// was never in) -- only what it drives through its pins: the relay command. The same
// pack with packsim's core still reports its state and balancing status from t = 0.
TEST(FirmwareRun, AUserFirmwareRunHasNoEventsOfTheCoresState) {
  const std::string pack = "hardware: {balancing: {resistor_ohm: 47}}\nrun: {duration_s: 2}\n";
  const RunResult user = runScenario(test::scenarioFromYaml("extends: firmware/c_example_firmware.yaml\n" + pack));
  for (const char* kind : {"bms_state", "balancing", "fault_active", "fault_latched", "fault_cleared", "precharge", "comm_lost"})
    EXPECT_TRUE(test::eventsOf(user, kind).empty()) << kind << ": " << test::eventsOf(user, kind).front()->detail;
  EXPECT_NEAR(test::eventTime(user, "relay", "close"), 0.41, 1e-9);  // its pin: precharge_ms 300 after the 110 ms task
  const RunResult core = runScenario(test::scenarioFromYaml("extends: bench_6s_ncr18650_2C.yaml\n" + pack));
  EXPECT_EQ(test::eventTime(core, "bms_state", "init"), 0.0);
  EXPECT_EQ(test::eventTime(core, "balancing"), 0.0);
}

}  // namespace
}  // namespace packsim

namespace packsim {
namespace {

// The recorded truth's mean cell SOC at the last sample at or before t_s.
double truthSocAt(const RunResult& r, double t_s) {
  double soc = -1.0;
  for (size_t i = 0; i < r.rec.time_s.size() && r.rec.time_s[i] <= t_s + 1e-9; ++i) soc = r.rec.soc_truth_mean[i];
  return soc;
}

// The number after `prefix` in the first firmware event starting with it (a percentage).
double firmwarePercent(const RunResult& r, const std::string& prefix, double& t_s) {
  for (const Event& e : r.events)
    if (e.kind == "firmware" && e.detail.rfind(prefix, 0) == 0) {
      t_s = e.time_s;
      const size_t at = e.detail.find("SOC ") + 4;
      return std::stod(e.detail.substr(at)) / 100.0;
    }
  t_s = -1.0;
  return -1.0;
}

// The bundled brown-out (scenarios/firmware/c_example_firmware_brownout.yaml), event by
// event, with its instants worked out by hand: the 7 V dip at 200 s stays above the
// 4 V threshold (no reset); the 0 V dip at 300 s is seen by the MCU at the 300 s tick:
// the reset, the outputs off at 300.000 s and the relay contact open after its open
// delay; the rail is back at 300.5 s: the boot (init at 300.5 s), the first read-out
// at 300.6 s, precharge at the 10 ms task of 300.61 s, the relay 300 ms later at
// 300.91 s (precharge_ms). The SOC the firmware resumes from NVM is within 1 % of the
// plant's mean cell SOC there (the record lags by at most its 5 s period: 0.26 % at
// 5.9 A), as its SOC from OCV at power-up was.
TEST(FirmwareRun, ABrownOutResetsTheExampleFirmwareWhichResumesItsSocFromNvm) {
  const Scenario s = loadScenarioFile(test::scenarioDir() + "/firmware/c_example_firmware_brownout.yaml");
  const RunResult r = runScenario(s);
  EXPECT_EQ(r.summary.firmware_status.rfind("example_bms 1.0: ran to the end", 0), 0u) << r.summary.firmware_status;
  EXPECT_FALSE(r.summary.tripped);
  EXPECT_NEAR(test::eventTime(r, "fault_injected", "supply_brownout to 7 V"), 200.0, 1e-9);
  int resets = 0;
  for (const Event& e : r.events) resets += e.kind == "mcu_reset";
  EXPECT_EQ(resets, 1) << "the 7 V dip rides through";
  EXPECT_NEAR(test::eventTime(r, "mcu_reset",
                              "brown-out: the 12 V supply at 0.00 V, below the MCU's 4.00 V brown-out threshold; held in "
                              "reset with its outputs off"),
              300.0, 1e-9);
  EXPECT_NEAR(test::eventTime(r, "relay_contact", "opened"), 300.0 + s.hardware.relay.open_delay_s, 1e-9);
  double loaded = -1.0;  // the second firmware_loaded: the boot after the reset
  for (const Event& e : r.events)
    if (e.kind == "firmware_loaded" && e.time_s > 0.0) loaded = e.time_s;
  EXPECT_NEAR(loaded, 300.5, 1e-9);
  EXPECT_NEAR(test::eventTime(r, "firmware", "precharge"), 0.11, 1e-9);  // power-up: read-out 0.1 s, task 0.11 s
  double precharge2 = -1.0, relay2 = -1.0, closed2 = -1.0;
  for (const Event& e : r.events) {
    if (e.time_s < 300.0) continue;
    if (e.kind == "firmware" && e.detail == "precharge" && precharge2 < 0) precharge2 = e.time_s;
    if (e.kind == "firmware" && e.detail == "relay closed" && relay2 < 0) relay2 = e.time_s;
    if (e.kind == "relay_contact" && e.detail.rfind("closed", 0) == 0 && closed2 < 0) closed2 = e.time_s;
  }
  EXPECT_NEAR(precharge2, 300.61, 1e-9);
  EXPECT_NEAR(relay2, 300.91, 1e-9);
  EXPECT_NEAR(closed2, 300.91 + s.hardware.relay.close_delay_s, 1e-9);

  double ocv_s = 0.0, boot_s = 0.0;
  const double fromOcv = firmwarePercent(r, "SOC ", ocv_s);
  const double resumed = firmwarePercent(r, "boot 1: SOC ", boot_s);
  ASSERT_GE(fromOcv, 0.0);
  ASSERT_GE(resumed, 0.0);
  EXPECT_NEAR(ocv_s, 0.1, 0.001);  // the first read-out
  EXPECT_NEAR(fromOcv, truthSocAt(r, ocv_s), 0.01);
  EXPECT_GT(boot_s, 300.5);
  EXPECT_LT(boot_s, 300.51);
  // The truth at the 300 s sample holds until the relay closes again at 300.91 s (no
  // current in between); the record the firmware resumes from was saved before 300 s.
  EXPECT_NEAR(resumed, truthSocAt(r, 300.0), 0.01);
  EXPECT_GE(resumed, truthSocAt(r, 300.0)) << "a record saved before the reset: no discharge after it counted";

  // The summary's line says what the events say.
  const std::string text = formatSummary(s, r);
  EXPECT_NE(text.find("MCU reset       300.000 s  brown-out: the 12 V supply at 0.00 V, below the MCU's 4.00 V "
                      "brown-out threshold; booted again at 300.500 s\n"),
            std::string::npos)
      << text;
  // packsim check: the expect block holds (one reset, no trip, the energy of a relay
  // closed again), and each dip's line says what the MCU did.
  const CheckOutcome o = judge(s, r);
  EXPECT_TRUE(o.failures.empty()) << (o.failures.empty() ? "" : o.failures[0]);
  const auto has = [&](const std::string& line) {
    return std::find(o.latencies.begin(), o.latencies.end(), line) != o.latencies.end();
  };
  EXPECT_TRUE(has("supply_brownout to 7 V @200.000 s: above the brown-out threshold, the MCU rode it through (no BMS "
                  "fault expected)"));
  EXPECT_TRUE(has("supply_brownout to 0 V @300.000 s: the MCU reset at 300.000 s (no BMS fault expected)"));
}

// The cases that contradict each printed line: without the deep dip there is no reset
// and no "MCU reset" line, and the relay stays closed; with the threshold above the
// 7 V dip (brownout_V: 8) that dip resets the MCU at 200 s, and the line says so.
TEST(FirmwareRun, ADipAboveTheBrownOutThresholdRidesThroughAndOneBelowResets) {
  const std::string base = "extends: firmware/c_example_firmware_brownout.yaml\n"
                           "faults: [{kind: supply_brownout, at_s: 200, duration_s: 1.0, supply_V: 7.0}]\n"
                           "run: {duration_s: 205}\n"
                           "expect: {mcu_resets: 1}\n";  // the bundled expect block's reset (its energy needs 360 s)
  const Scenario ride = test::scenarioFromYaml(base);
  const RunResult a = runScenario(ride);
  EXPECT_EQ(test::eventTime(a, "mcu_reset"), -1.0);
  EXPECT_EQ(test::eventTime(a, "relay_contact", "opened"), -1.0);
  EXPECT_EQ(formatSummary(ride, a).find("MCU reset"), std::string::npos);
  const CheckOutcome ridden = judge(ride, a);
  ASSERT_EQ(ridden.failures.size(), 1u);
  EXPECT_EQ(ridden.failures[0], "expected 1 MCU resets, got 0");

  const Scenario low = test::scenarioFromYaml(base + "hardware: {mcu_supply: {brownout_V: 8}}\n");
  const RunResult b = runScenario(low);
  EXPECT_NEAR(test::eventTime(b, "mcu_reset", "brown-out: the 12 V supply at 7.00 V, below the MCU's 8.00 V"), 200.0,
              1e-9);
  EXPECT_NE(formatSummary(low, b).find("MCU reset       200.000 s  brown-out: the 12 V supply at 7.00 V, below the "
                                        "MCU's 8.00 V brown-out threshold; booted again at 201.000 s\n"),
            std::string::npos)
      << formatSummary(low, b);
  const CheckOutcome reset = judge(low, b);
  EXPECT_TRUE(reset.failures.empty()) << (reset.failures.empty() ? "" : reset.failures[0]);
  EXPECT_NE(std::find(reset.latencies.begin(), reset.latencies.end(),
                      "supply_brownout to 7 V @200.000 s: the MCU reset at 200.000 s (no BMS fault expected)"),
            reset.latencies.end());
  const std::string bad = test::yamlErrorOf(base + "hardware: {mcu_supply: {brownout_V: 13}}\n");
  EXPECT_NE(bad.find("hardware.mcu_supply.brownout_V"), std::string::npos) << bad;
  EXPECT_NE(bad.find("below nominal_V (12 V)"), std::string::npos) << bad;
}

}  // namespace
}  // namespace packsim
