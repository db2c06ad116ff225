// packsim's own core runs only as a firmware on the contract (bms/bms_firmware.hpp):
// loaded by the firmware host like any other firmware, reading its monitor ICs over the
// bus at its configured rates (bms.readout), its configuration blob checked at init.
#include <bms/bms_firmware.hpp>
#include <gtest/gtest.h>

#include <cmath>

#include "core/firmware/firmware_host.hpp"
#include "core/sim/bms_bridge.hpp"
#include "core/sim/simulation.hpp"
#include "test_support.hpp"

namespace packsim {
namespace {

// 2 cells under a 20 A load: the truth moves every tick (the RC pair charging, SOC).
std::string twoCells(const std::string& bms) {
  return test::simpleCellYaml(2) + "bms: {tick_ms: 10" + bms + "}\nload: {current_A: 20}\n" +
         "run: {duration_s: 6}\noutput: {interval_s: 0.01}\n";
}

TEST(CoreFirmware, IsLoadedByTheFirmwareHostWithItsTasks) {
  const RunResult r = runScenario(test::scenarioFromYaml(twoCells("")));
  EXPECT_EQ(test::eventTime(r, "firmware_loaded", "'packsim core' (3 tasks, "), 0.0);
  EXPECT_TRUE(r.summary.firmware_status.empty()) << "the core ran to the end: no firmware line";
}

// With a 1 s read-out the cell readings the core holds change only once a second (at
// the read-out), while the truth moves every tick; read every tick they follow it.
TEST(CoreFirmware, ReadsItsMonitorsAtTheConfiguredPeriod) {
  for (int period_ms : {10, 1000}) {
    const RunResult r = runScenario(
        test::scenarioFromYaml(twoCells(period_ms == 10 ? "" : ", readout: {period_ms: " + std::to_string(period_ms) + "}")));
    const Recording& rec = r.rec;
    int changes = 0, offGrid = 0;
    for (size_t i = 1; i < rec.time_s.size(); ++i) {
      // From the first read-out after power-up (the one at init shows at the first tick).
      if (rec.time_s[i] < period_ms * 1e-3 - 1e-9) continue;
      if (rec.meas_cell_voltage_mV[i * 2] == rec.meas_cell_voltage_mV[(i - 1) * 2]) continue;
      ++changes;
      const double t = rec.time_s[i];
      if (std::fabs(t - std::round(t * 1000.0 / period_ms) * period_ms / 1000.0) > 1e-9) ++offGrid;
    }
    EXPECT_EQ(offGrid, 0) << period_ms << " ms: a reading changed between read-outs";
    if (period_ms == 1000) EXPECT_LE(changes, 6);
    else EXPECT_GT(changes, 50) << "read every tick, the reading follows the falling voltage";
  }
}

// Comm loss counts every read of a device: at 5 bad reads, a silent device is lost 4
// reads after the first. Reads every 5 s alone: 20 s; with alert polls every 0.5 s in
// between: 2 s.
TEST(CoreFirmware, AlertPollsBetweenReadOutsCountForCommLoss) {
  const std::string base = test::simpleCellYaml(2) +
                           "load: {current_A: 1}\nrun: {duration_s: 40, stop_after_trip_s: 1}\n"
                           "faults: [{kind: device_silent, device: 1, at_s: 10}]\n";
  const auto detected = [&](const std::string& readout) {
    const RunResult r = runScenario(test::scenarioFromYaml(base + "bms: {tick_ms: 10, readout: " + readout + "}\n"));
    return test::eventTime(r, "fault_active", "comm_loss") - 10.0;
  };
  EXPECT_NEAR(detected("{period_ms: 5000}"), 20.0, 1e-6);
  EXPECT_NEAR(detected("{period_ms: 5000, alert_period_ms: 500}"), 2.0, 1e-6);
}

struct Sink : FirmwareSink {
  std::vector<std::string> events;
  void event(double, const std::string& kind, const std::string& detail) override { events.push_back(kind + ": " + detail); }
  void trip(double, const std::string&) override {}
};

// An image of another layout (another build, a truncated file) never runs: init refuses
// it and the host stops the firmware.
TEST(CoreFirmware, RefusesAConfigurationImageOfAnotherLayout) {
  const Scenario s = test::scenarioFromYaml(twoCells(""));
  const std::vector<uint8_t> good = coreImage(makeBmsConfig(s));
  std::vector<uint8_t> truncated(good.begin(), good.end() - 4), wrongTag = good;
  wrongTag[0] ^= 0xFF;
  for (const auto& blob : {truncated, wrongTag}) {
    Sink sink;
    FirmwareHost host(bms::coreFirmware(), blob, FirmwareBoard{}, 0.01, sink);
    bms::Inputs in{};
    bms::Outputs out{};
    host.step(0.0, in, out);
    EXPECT_TRUE(host.dead());
    EXPECT_NE(host.faultCause().find("init returned"), std::string::npos) << host.faultCause();
  }
}

TEST(CoreFirmware, ReadOutRatesAreCheckedAtLoad) {
  const std::string base = test::simpleCellYaml(1) + test::kSimpleLoadYaml;
  EXPECT_NE(test::yamlErrorOf(base + "bms: {tick_ms: 10, readout: {period_ms: 15}}\n")
                .find("bms.readout.period_ms: period_ms = 15 is not a multiple of bms.tick_ms (10)"),
            std::string::npos);
  EXPECT_NE(test::yamlErrorOf(base + "bms: {tick_ms: 10, readout: {period_ms: 500, alert_period_ms: 500}}\n")
                .find("alert_period_ms: must be shorter than period_ms (500 ms)"),
            std::string::npos)
      << test::yamlErrorOf(base + "bms: {tick_ms: 10, readout: {period_ms: 500, alert_period_ms: 500}}\n");
  EXPECT_NE(test::yamlErrorOf(base + "bms: {readout: {perod_ms: 500}}\n").find("did you mean 'period_ms'"),
            std::string::npos);
}

}  // namespace
}  // namespace packsim
