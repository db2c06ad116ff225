// packsim's own core (bms/, C++) in target mode: packsim_core_cm4.elf, the same sources
// cross-compiled with the board-support layer, on the virtual Cortex-M4 with the image
// host mode flashes (bms.firmware: {target: cortex-m4} without elf, or `--target`).
// Independent expectation: host mode's run of the same scenario -- the same decisions
// (every bms_state, fault, relay and balancing event, the trip's reason and time to
// within one tick), the same BMS channels read from the core's RAM.
//
// The scenarios: one per monitor part (each on its reference system; system D's pack of
// several boards is not emulated), each a whole bundled scenario with a trip, chosen
// for a short run (the emulated core costs
// 10-30x host mode's CPU time: every bundled scenario is compared by
// scripts/compare_target.py, docs/firmware.md "Host mode against target mode").
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>

#include "core/cli/commands.hpp"
#include "core/scenario/scenario_error.hpp"
#include "core/scenario/target_switch.hpp"
#include "core/sim/simulation.hpp"
#include "test_support.hpp"

namespace packsim {
namespace {

#ifdef PACKSIM_TARGET_ELF_DIR
#define REQUIRE_ARM_TOOLCHAIN()
#else
#define REQUIRE_ARM_TOOLCHAIN() GTEST_SKIP() << "arm-none-eabi-gcc was not found when packsim was configured: no target ELF"
#endif

std::string scenarioPath(const std::string& name) { return test::scenarioDir() + "/" + name + ".yaml"; }

// The run's decisions: every event but the relay contact's instant (it follows the
// code's cycles) and the firmware_loaded line.
std::vector<Event> decisions(const RunResult& r) {
  std::vector<Event> out;
  for (const Event& e : r.events)
    if (e.kind != "relay_contact" && e.kind != "firmware_loaded") out.push_back(e);
  return out;
}

class CoreOnTarget : public ::testing::TestWithParam<std::string> {};

TEST_P(CoreOnTarget, DecidesAsInHostMode) {
  REQUIRE_ARM_TOOLCHAIN();
  const Scenario hs = loadScenarioFile(scenarioPath(GetParam()));
  const Scenario ts = loadScenarioOnTarget(scenarioPath(GetParam()), {}, "cortex-m4");
  ASSERT_TRUE(ts.bms.firmware.isTarget());
  ASSERT_FALSE(ts.bms.firmware.library);  // packsim's core, not a user firmware
  const RunResult host = runScenario(hs), target = runScenario(ts);

  ASSERT_TRUE(host.summary.tripped) << GetParam();
  ASSERT_TRUE(target.summary.tripped) << GetParam();
  EXPECT_EQ(target.summary.trip_reason, host.summary.trip_reason);
  EXPECT_NEAR(target.summary.trip_time_s, host.summary.trip_time_s, hs.bms.tick_s + 1e-9);
  EXPECT_EQ(target.summary.firmware_status, "");  // the core ran to the end

  const std::vector<Event> h = decisions(host), t = decisions(target);
  ASSERT_EQ(h.size(), t.size());
  for (size_t i = 0; i < h.size(); ++i) {
    EXPECT_EQ(t[i].kind, h[i].kind) << i;
    EXPECT_EQ(t[i].detail, h[i].detail) << h[i].kind << " at " << h[i].time_s;
    EXPECT_NEAR(t[i].time_s, h[i].time_s, hs.bms.tick_s + 1e-9) << h[i].kind << " " << h[i].detail;
  }
  // The channels the probe reads out of the MCU's RAM: the same state and faults at
  // every sample, the same measured cells (a misread layout would scramble them) but
  // for a code's rounding: the code's cycles move a conversion by microseconds of the
  // truth (the LTC6813's, 0.1 % of its cell readings by 1 mV).
  EXPECT_EQ(target.rec.bms_state, host.rec.bms_state);
  EXPECT_EQ(target.rec.fault_latched, host.rec.fault_latched);
  ASSERT_EQ(target.rec.meas_cell_voltage_mV.size(), host.rec.meas_cell_voltage_mV.size());
  size_t same = 0;
  int worst_mV = 0;
  for (size_t i = 0; i < host.rec.meas_cell_voltage_mV.size(); ++i) {
    same += target.rec.meas_cell_voltage_mV[i] == host.rec.meas_cell_voltage_mV[i];
    worst_mV = std::max(worst_mV, std::abs(target.rec.meas_cell_voltage_mV[i] - host.rec.meas_cell_voltage_mV[i]));
  }
  EXPECT_LE(worst_mV, 1);
  EXPECT_GE(static_cast<double>(same), 0.99 * static_cast<double>(host.rec.meas_cell_voltage_mV.size()));

  // The emulated core's counts in the summary: per task, and the run's load and stack.
  ASSERT_GE(target.summary.firmware_target.size(), 2u);
  EXPECT_NE(target.summary.firmware_target.front().find("task 0 ("), std::string::npos);
  EXPECT_NE(target.summary.firmware_target.back().find("CPU load"), std::string::npos);
  EXPECT_TRUE(host.summary.firmware_target.empty());
}

std::string testName(const ::testing::TestParamInfo<std::string>& info) {
  std::string n = info.param;
  std::replace(n.begin(), n.end(), '/', '_');
  return n;
}

INSTANTIATE_TEST_SUITE_P(Bundled, CoreOnTarget,
                         ::testing::Values("faults/a_thermistor_open", // system A, BQ76PL455A daisy chain
                                           "bench_6s_ncr18650_2C",     // system C, BQ76PL536A stack
                                           "faults/e_channel_gain",    // system E, BQ76952 (its own FETs)
                                           "faults/fs_isospi_break"),  // formula student, LTC6813-1 isoSPI
                         testName);

// --target on a scenario that runs a user's library in host mode: not run, and why.
TEST(CoreOnTargetSwitch, RefusesAHostModeLibraryByName) {
  REQUIRE_ARM_TOOLCHAIN();
  try {
    (void)loadScenarioOnTarget(scenarioPath("firmware/c_example_firmware"), {}, "cortex-m4");
    FAIL() << "no error";
  } catch (const NotOnTarget& e) {
    EXPECT_NE(std::string(e.what()).find("runs the firmware library"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("elf:"), std::string::npos) << e.what();
  }
}

// `packsim check --target`: a library scenario is a SKIP line with its reason and
// counted as skipped, not a failure (exit 0 when the rest passed).
TEST(CoreOnTargetSwitch, CheckSkipsALibraryScenario) {
  REQUIRE_ARM_TOOLCHAIN();
  CheckOptions o;
  o.paths = {scenarioPath("firmware/c_example_firmware")};
  o.target = "cortex-m4";
  testing::internal::CaptureStdout();
  const int rc = cmdCheck(o);
  const std::string out = testing::internal::GetCapturedStdout();
  EXPECT_EQ(rc, 0) << out;
  EXPECT_EQ(out.rfind("SKIP  ", 0), 0u) << out;
  EXPECT_NE(out.find("0 passed, 0 failed, 1 skipped"), std::string::npos) << out;
}

// A scenario already on the target runs as it is (its own ELF, not the core).
TEST(CoreOnTargetSwitch, LeavesATargetScenarioAsItIs) {
  REQUIRE_ARM_TOOLCHAIN();
  const Scenario s = loadScenarioOnTarget(scenarioPath("firmware/target/c_example_firmware_cm4"), {}, "cortex-m4");
  EXPECT_TRUE(s.bms.firmware.library);
  EXPECT_NE(s.bms.firmware.library_path.find("packsim_example_bms_cm4.elf"), std::string::npos);
}

// Several monitor boards (one MCU each) are not emulated: an error at devices_per_board.
TEST(CoreOnTargetSwitch, RefusesSeveralBoards) {
  REQUIRE_ARM_TOOLCHAIN();
  const std::string e = test::scenarioErrorOf([] {
    (void)loadScenarioOnTarget(scenarioPath("motorcycle_110s"), {}, "cortex-m4");  // 19 devices, 6 per board
  });
  EXPECT_NE(e.find("devices_per_board"), std::string::npos) << e;
  EXPECT_NE(e.find("one MCU"), std::string::npos) << e;
}

// The core takes its configuration from the bms settings: a blob beside it is an error.
TEST(CoreOnTargetSwitch, RefusesABlobForTheCore) {
  REQUIRE_ARM_TOOLCHAIN();
  const std::string e = test::yamlErrorOf(test::simpleCellYaml(4) + test::kSimpleLoadYaml +
                                          "bms:\n  firmware:\n    target: cortex-m4\n    config: {a: 1}\n");
  EXPECT_NE(e.find("bms.firmware.config"), std::string::npos) << e;
  EXPECT_NE(e.find("bms settings"), std::string::npos) << e;
}

}  // namespace
}  // namespace packsim
