// The LTC6811-1 / LTC6813-1 as registered parts, run end to end with packsim's own
// firmware core: the scenario selects the part, the core reads the register-level chain
// through its driver, and what the core saw is judged against the plant's truth --
// cells within the part's 100 uV LSB and the noise, GPIO thermistors against the cell
// temperature they sit on, an isoSPI break silencing the devices beyond it until the
// BMS trips on comm loss, and DCC bits bleeding exactly the cells the BMS chose, at the
// charge and energy their resistor carries.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "core/scenario/load_scenario.hpp"
#include "core/sim/simulation.hpp"
#include "test_support.hpp"

namespace packsim {
namespace {

std::string ltcPack(const std::string& model, int series, const std::string& afeExtra, const std::string& extra) {
  return "name: ltc\nseed: 3\npack:\n  series: " + std::to_string(series) +
         "\n  initial_soc: 0.6\n  cell: {preset: ncr18650_3p1Ah}\n"
         "  spread: {level: group, initial_soc_sd: 0.02}\n"
         "hardware:\n  afe: {model: " + model + afeExtra + "}\n" + extra;
}

// A 36s pack on two LTC6813s under a 6 A load: every cell the core holds is the truth
// at the read-out to the 100 uV LSB, the firmware's 1 mV rounding and 5 sigma of the
// 0.1 mV rms noise; with the noise off, within the LSB and the rounding alone.
TEST(Ltc681xPart, CoreReadsTheLtc6813CellsToTheirLsbAndNoise) {
  for (double noise_mV : {0.1, 0.0}) {
    const Scenario s = test::scenarioFromYaml(
        ltcPack("ltc6813", 36, ", cells_per_device: 18, thermistors_per_device: 2",
                "  cell_adc: {noise_mV_rms: " + std::to_string(noise_mV) + "}\n"
                "  thermistors: {at_groups: [1, 10, 19, 28]}\n"
                "bms: {tick_ms: 100}\nload: {current_A: 6}\nrun: {duration_s: 60}\noutput: {interval_s: 0.1}\n"));
    const RunResult r = runScenario(s);
    ASSERT_FALSE(r.summary.tripped) << r.summary.trip_reason;
    EXPECT_NE(test::eventTime(r, "firmware_loaded", "'packsim core' (3 tasks, 18464 bytes RAM, 1216 bytes"), -1.0)
        << "the core's RAM and image are the ones of any part with the 18-cell part";
    const Recording& rec = r.rec;
    const size_t n = 36;
    const double bound_mV = 0.5 + 0.05 + 5.0 * noise_mV + 0.02;  // + the voltage's drift within one tick
    double worst = 0.0;
    size_t compared = 0;
    // From 1 s on: the load is constant from the relay's closing (0.2 s).
    for (size_t i = test::sampleAt(rec, 1.0); i < rec.samples(); ++i)
      for (size_t c = 0; c < n; ++c) {
        // The core's reading is the read-out of the previous tick: the truth then.
        const double truth_mV = rec.cell_voltage_V[(i - 1) * n + c] * 1e3;
        const double err = std::abs(rec.meas_cell_voltage_mV[i * n + c] - truth_mV);
        worst = std::max(worst, err);
        EXPECT_LE(err, bound_mV) << "t " << rec.time_s[i] << " cell " << c + 1;
        ++compared;
      }
    EXPECT_EQ(compared, (rec.samples() - test::sampleAt(rec, 1.0)) * n);
    for (uint8_t bad : rec.comm_bad) EXPECT_EQ(bad, 0);
    RecordProperty(noise_mV > 0 ? "worst_mV_noisy" : "worst_mV_quiet", std::to_string(worst));
  }
}

// GPIO thermistors: cell 10 heated by 3 W from 20 s; its thermistor (GPIO1 of the 2nd
// LTC6811) follows the cell's temperature, and so do the others at rest, to the
// firmware's 0.1 C and the ADC's 100 uV on a 3 V divider (~0.004 C at 25 C).
TEST(Ltc681xPart, GpioThermistorsReadTheirCellsTemperature) {
  const Scenario s = test::scenarioFromYaml(
      ltcPack("ltc6811", 24, ", cells_per_device: 12, thermistors_per_device: 2",
              "  thermistors: {at_groups: [1, 6, 10, 20]}\n"
              "bms: {tick_ms: 100}\nload: {current_A: 2}\nrun: {duration_s: 300}\noutput: {interval_s: 1}\n"
              "faults:\n  - {kind: hot_cell, cell: 10, heat_W: 3, at_s: 20}\n"));
  const RunResult r = runScenario(s);
  ASSERT_FALSE(r.summary.tripped) << r.summary.trip_reason;
  const Recording& rec = r.rec;
  const size_t n = 24, k = 4;
  const size_t groups[k] = {0, 5, 9, 19};
  double rise = 0.0;
  for (size_t i = 1; i < rec.samples(); ++i)
    for (size_t j = 0; j < k; ++j) {
      // The core's reading is the read-out of this sample's tick (at most 0.1 s old).
      const double truth_C = rec.cell_temp_C[i * n + groups[j]];
      const double meas_C = rec.meas_temperature_dC[i * k + j] * 0.1;
      // 0.05 C rounding, 0.01 C the ADC, a cell heating < 0.1 C/s for 0.1 s.
      EXPECT_NEAR(meas_C, truth_C, 0.07) << "t " << rec.time_s[i] << " thermistor " << j + 1;
      if (j == 2) rise = std::max(rise, meas_C - rec.meas_temperature_dC[2] * 0.1);
    }
  EXPECT_GT(rise, 5.0) << "the heated cell's thermistor saw it heat";
}

// An isoSPI link broken above the 2nd of four LTC6811s at 30 s: devices 3 and 4 hear
// nothing (their slots read 0xFF, no valid PEC), 1 and 2 read on; the core counts the
// bad read-outs (at 30.0, 30.1 and 30.2 s: the read-out at 30.0 s already sees the
// break) and trips on comm loss at the 3rd, losing devices 3 and 4 only.
TEST(Ltc681xPart, BrokenIsoSpiLinkSilencesTheDevicesBeyondAndTheBmsTrips) {
  const Scenario s = test::scenarioFromYaml(
      ltcPack("ltc6811", 48, ", cells_per_device: 12, thermistors_per_device: 1",
              "  thermistors: {at_groups: [1, 13, 25, 37]}\n"
              "bms:\n  tick_ms: 100\n  comm_loss_count: 3\n  protections: {comm_loss: {action: isolate}}\n"
              "load: {current_A: 5}\nrun: {duration_s: 60, stop_after_trip_s: 2}\noutput: {interval_s: 0.1}\n"
              "faults:\n  - {kind: broken_link, above_device: 2, byte: 255, at_s: 30}\n"));
  const RunResult r = runScenario(s);
  ASSERT_TRUE(r.summary.tripped);
  EXPECT_EQ(r.summary.trip_reason, "comm_loss");
  const double trip = test::eventTime(r, "fault_active", "comm_loss");
  EXPECT_NEAR(trip, 30.2, 1e-6);
  EXPECT_NEAR(test::eventTime(r, "comm_lost", "device 3"), 30.2, 1e-6);
  EXPECT_NEAR(test::eventTime(r, "comm_lost", "device 4"), 30.2, 1e-6);
  EXPECT_EQ(test::eventTime(r, "comm_lost", "device 1"), -1.0);
  EXPECT_EQ(test::eventTime(r, "comm_lost", "device 2"), -1.0);
  const Recording& rec = r.rec;
  const size_t devices = 4;
  const size_t last = rec.samples() - 1;
  for (size_t d = 0; d < devices; ++d) {
    if (d < 2) {
      for (size_t i = 0; i <= last; ++i) EXPECT_EQ(rec.comm_bad[i * devices + d], 0) << "device " << d + 1;
    } else {
      EXPECT_EQ(rec.comm_bad[test::sampleAt(rec, 29.9) * devices + d], 0) << "device " << d + 1;
      EXPECT_GE(rec.comm_bad[last * devices + d], 3) << "device " << d + 1;
    }
  }
}

// A device that stops answering on a 10 ms read-out: the chain's recovery (wake pulses,
// the configuration written again, the references' 4.4 ms power-up) and a read-out
// (7.5 ms for two LTC6811s at 7 kHz) do not both fit the period, so the driver recovers
// on one call and reads on the next. Before, it did both on every call while the device
// stayed silent: 10.8 ms of a 10 ms period, and packsim's own firmware died on its
// deadline ("contract break") instead of tripping. Now every fault of the device trips
// on comm_loss after its 5 bad read-outs, every other call: within 10 periods and a tick.
TEST(Ltc681xPart, ADeviceLostOnATenMillisecondReadoutTripsOnCommLossWithinItsPeriod) {
  for (const char* fault : {"{kind: device_silent, device: 2, at_s: 5.0007}",
                            "{kind: crc_errors, device: 2, rate: 1, at_s: 5.0007}",
                            "{kind: device_stuck, device: 2, byte: 255, at_s: 5.0007}"}) {
    const Scenario s = test::scenarioFromYaml(
        "name: ltc10ms\nseed: 5\n"
        "pack: {series: 14, parallel: 2, initial_soc: 0.7, cell: {preset: ncr18650_3p1Ah}}\n"
        "hardware:\n  afe: {model: ltc6811, cells_per_device: 7, thermistors_per_device: 2}\n"
        "  thermistors: {at_groups: [1, 7, 8, 14]}\n"
        "bms: {tick_ms: 10, protections: {overcurrent_discharge: {threshold_A: 20, delay_ms: 200}}}\n"
        "load: {current_A: 8}\nrun: {duration_s: 6}\n"
        "faults: [" + std::string(fault) + "]\n");
    const RunResult r = runScenario(s);
    EXPECT_EQ(test::eventsOf(r, "firmware_fault").size(), 0u) << fault;
    const double lost = test::eventTime(r, "comm_lost", "device 2");
    EXPECT_GT(lost, 5.0007) << fault;
    EXPECT_LE(lost, 5.0007 + 0.11) << fault;
    EXPECT_EQ(test::eventTime(r, "comm_lost", "device 1"), -1.0) << fault;
    EXPECT_EQ(r.summary.trip_reason, "comm_loss") << fault;
  }
}

// Passive balancing through the DCC bits: an LTC6813 pair on a charger, cells 5 and 16
// (CFGRA's DCC5 on device 1, CFGRB's DCC16 on device 1) and 30 (device 2) start high;
// the switches that are on are exactly the cells the BMS commanded, the high ones among
// them, each carrying V/R; the energy its resistor took is the integral of V^2/R, and
// the charge it bled is the SOC it lost against the cell that bled least.
TEST(Ltc681xPart, DccBitsBleedTheCommandedCellsAtVSquaredOverR) {
  const Scenario s = test::scenarioFromYaml(
      "name: ltc_balance\nseed: 3\npack:\n  series: 36\n  initial_soc: 0.80\n"
      "  cell: {preset: ncr18650_3p1Ah}\n"
      "  cells:\n    - {cell: 5, initial_soc: 0.90}\n    - {cell: 16, initial_soc: 0.90}\n"
      "    - {cell: 30, initial_soc: 0.88}\n"
      "hardware:\n  afe: {model: ltc6813, cells_per_device: 18, thermistors_per_device: 1}\n"
      "  thermistors: {at_groups: [1, 19]}\n"
      "  balancing: {resistor_ohm: 33, rds_on_ohm: 0.0}\n"
      "bms:\n  tick_ms: 1000\n  charge_full_cell_V: 4.18\n  balance_time_s: 60\n"
      "  balancing: {when: charging, start_delta_mV: 20, stop_delta_mV: 5, min_cell_V: 3.3}\n"
      "load:\n  charger: {current_A: 0.3, voltage_V: 151.2, end_current_A: 0.05}\n"
      "run: {duration_s: 1800}\noutput: {interval_s: 1}\n");
  const RunResult r = runScenario(s);
  ASSERT_FALSE(r.summary.tripped) << r.summary.trip_reason;
  const Recording& rec = r.rec;
  ASSERT_TRUE(rec.has_balancing);
  const size_t n = 36;
  const double R = 33.0;
  std::vector<double> bleed_As(n, 0.0), v2r_J(n, 0.0);
  std::vector<int> onSamples(n, 0);
  for (size_t i = 1; i < rec.samples(); ++i) {
    const double dt = rec.time_s[i] - rec.time_s[i - 1];
    for (size_t c = 0; c < n; ++c) {
      const double I = rec.balance_current_A[i * n + c], V = rec.cell_voltage_V[i * n + c];
      // A switch on is a cell the BMS commanded (the DCC bits go out at the tick the
      // mask changes; the sample after it shows them). A sample where the switch
      // changed carries the step before it: judged only where it held.
      const bool on = rec.hw_balancing[i * n + c], held = on == rec.hw_balancing[(i - 1) * n + c];
      if (on) {
        EXPECT_TRUE(rec.balance_mask[i * n + c] || rec.balance_mask[(i - 1) * n + c])
            << "t " << rec.time_s[i] << " cell " << c + 1 << " bleeds uncommanded";
        if (held) EXPECT_NEAR(I, V / R, 2e-3 * V / R) << "t " << rec.time_s[i] << " cell " << c + 1;
        ++onSamples[c];
        v2r_J[c] += V * V / R * dt;
      } else if (held) {
        EXPECT_EQ(I, 0.0) << "t " << rec.time_s[i] << " cell " << c + 1;
      }
      bleed_As[c] += I * dt;
    }
  }
  for (size_t c : {4u, 15u, 29u}) {
    EXPECT_GT(onSamples[c], 300) << "cell " << c + 1 << " bled";
    RecordProperty("cell_" + std::to_string(c + 1) + "_J", std::to_string(v2r_J[c]));
  }
  // 36 cells, three high: the others bled far less than the high ones.
  for (size_t c = 0; c < n; ++c)
    if (c != 4 && c != 15 && c != 29) EXPECT_LT(bleed_As[c], 0.2 * bleed_As[4]) << "cell " << c + 1;
  test::expectBleedIsTheSocLost(rec, bleed_As, 3.1 * 3600.0, 2.0);
}

// Load errors name the key and the part's limit: a chain longer than the driver holds,
// more cells or GPIO thermistors than the part has, comparators the wrong way round.
TEST(Ltc681xPart, LoadErrorsNameTheKeyAndTheLimit) {
  auto errorOf = [](int series, const std::string& afe) {
    return test::yamlErrorOf(ltcPack("ltc6811", series, afe, "load: {current_A: 1}\nrun: {duration_s: 1}\n"));
  };
  const std::string chain = errorOf(204, ", cells_per_device: 12");
  EXPECT_NE(chain.find("hardware.afe.devices"), std::string::npos) << chain;
  EXPECT_NE(chain.find("17 devices on one isoSPI chain"), std::string::npos) << chain;
  EXPECT_NE(chain.find("at most 16"), std::string::npos) << chain;
  EXPECT_EQ(errorOf(204, ", cells_per_device: 12, devices_per_board: 9"), "<no error>");
  const std::string cells = errorOf(24, ", cells_per_device: 13");
  EXPECT_NE(cells.find("hardware.afe.cells_per_device"), std::string::npos) << cells;
  EXPECT_NE(cells.find("12"), std::string::npos) << cells;
  const std::string gpios = errorOf(24, ", thermistors_per_device: 6");
  EXPECT_NE(gpios.find("hardware.afe.thermistors_per_device"), std::string::npos) << gpios;
  const std::string cmp = errorOf(24, ", uv_V: 3.0, ov_V: 2.9");
  EXPECT_NE(cmp.find("hardware.afe.ov_V"), std::string::npos) << cmp;
  const std::string baud = errorOf(24, ", baud: 2000000");
  EXPECT_NE(baud.find("hardware.afe.baud"), std::string::npos) << baud;
  EXPECT_NE(baud.find("at most 1000000"), std::string::npos) << baud;
  const std::string lsb = test::yamlErrorOf(
      ltcPack("ltc6813", 18, "", "  cell_adc: {lsb_uV: 200}\nload: {current_A: 1}\nrun: {duration_s: 1}\n"));
  EXPECT_NE(lsb.find("reports cells in 100 uV codes"), std::string::npos) << lsb;
}

}  // namespace
}  // namespace packsim
