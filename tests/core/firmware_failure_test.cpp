// A user firmware that fails -- does not load, was built for another contract version,
// fails its init, crashes or hangs -- is a failed run (issue 28): `packsim run` exits 1
// naming the firmware file and the failure, `packsim check` fails with that reason;
// before, `run` exited 0 after simulating a dead MCU and `check` said only "no trip".
// A scenario that means its firmware to fail says expect: {firmware_fault: true}; a
// host killed on purpose by the host_dead fault is not a firmware failure.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/check/check.hpp"
#include "core/sim/firmware_failure.hpp"
#include "core/sim/simulation.hpp"
#include "test_support.hpp"

namespace packsim {
namespace {

namespace fs = std::filesystem;

std::string readText(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

struct Cli {
  int rc;
  std::string out, err;
};

Cli cli(const std::string& args, const fs::path& dir) {
  const int rc = std::system((std::string(PACKSIM_BINARY) + " " + args + " >" + (dir / "out.txt").string() + " 2>" +
                              (dir / "err.txt").string())
                                 .c_str());
  return {WIFEXITED(rc) ? WEXITSTATUS(rc) : -1, readText(dir / "out.txt"), readText(dir / "err.txt")};
}

// System C's bench pack for 5 s on `library` with the probe's `mode` (tests/firmware/probe_fw.c).
std::string benchWith(const std::string& library, int mode, const std::string& expect) {
  return "extends: " + test::scenarioDir() + "/bench_6s_ncr18650_2C.yaml\n"
         "name: fw_fail\n"
         "bms: {tick_ms: 10, firmware: {library: " + library + ", watchdog_ms: 200, config: {mode: " +
         std::to_string(mode) + ", at_ms: 50}}}\n"
         "load: {current_A: 1.0}\nrun: {duration_s: 5}\n" + expect;
}

struct Case {
  const char* name;
  std::string library;
  int mode;
  const char* cause;
};

std::vector<Case> cases(const fs::path& dir) {
  std::ofstream(dir / "not_a_library.so") << "this is not a shared library\n";
  return {{"does not load", (dir / "not_a_library.so").string(), 0, "not_a_library.so"},
          {"ABI mismatch", PACKSIM_ABI_MISMATCH_FW, 0, "ABI mismatch: the firmware was built against contract version"},
          {"init fails", PACKSIM_PROBE_FW, 6, "init returned 7 (not 0)"},
          {"crash", PACKSIM_PROBE_FW, 2, "crash in task 0 (period 10 ms): SIGSEGV"},
          {"hang", PACKSIM_PROBE_FW, 3, "hang in task 0 (period 10 ms)"}};
}

TEST(FirmwareFailure, RunExitsOneAndCheckFailsWithTheReason) {
  const fs::path dir = test::freshTempDir("packsim_fwfail_", "run");
  for (const Case& c : cases(dir)) {
    SCOPED_TRACE(c.name);
    const fs::path yaml = dir / "s.yaml";
    std::ofstream(yaml) << benchWith(c.library, c.mode, "expect: {min_cell_V_above: 2.0}\n");
    const fs::path out = dir / "r.h5";
    const Cli run = cli("run " + yaml.string() + " -o " + out.string(), dir);
    EXPECT_EQ(run.rc, 1) << run.err;
    EXPECT_NE(run.err.find("the firmware library '" + c.library + "' failed at "), std::string::npos) << run.err;
    EXPECT_NE(run.err.find(c.cause), std::string::npos) << run.err;
    const Cli check = cli("check " + yaml.string(), dir);
    EXPECT_EQ(check.rc, 1) << check.out;
    EXPECT_NE(check.out.find("FAIL  " + yaml.string()), std::string::npos) << check.out;
    EXPECT_NE(check.out.find(c.cause), std::string::npos) << check.out;
  }
}

// The same failures, meant: exit 0 and PASS; and expecting one that does not come fails.
TEST(FirmwareFailure, AnExpectedFirmwareFaultPasses) {
  const fs::path dir = test::freshTempDir("packsim_fwfail_", "expected");
  const fs::path yaml = dir / "s.yaml";
  std::ofstream(yaml) << benchWith(PACKSIM_PROBE_FW, 2, "expect: {firmware_fault: true}\n");
  const Cli run = cli("run " + yaml.string() + " -o " + (dir / "r.h5").string(), dir);
  EXPECT_EQ(run.rc, 0) << run.err;
  const Cli check = cli("check " + yaml.string(), dir);
  EXPECT_EQ(check.rc, 0) << check.out;
  EXPECT_NE(check.out.find("PASS  " + yaml.string()), std::string::npos) << check.out;

  const Scenario healthy = test::scenarioFromYaml(benchWith(PACKSIM_PROBE_FW, 0, "expect: {firmware_fault: true}\n"));
  const RunResult r = runScenario(healthy);
  EXPECT_EQ(firmwareFailure(healthy, r), "");
  const CheckOutcome o = judge(healthy, r);
  ASSERT_EQ(o.failures.size(), 1u);
  EXPECT_EQ(o.failures[0], "expected a firmware_fault, but the firmware ran to the end");
}

// A host killed on purpose (the host_dead fault) is no firmware failure: exit 0.
TEST(FirmwareFailure, AHostKilledOnPurposeIsNoFailure) {
  const fs::path dir = test::freshTempDir("packsim_fwfail_", "host_dead");
  const Cli run = cli("run faults/a_host_dead --set run.duration_s=400 -q -o " + (dir / "r.h5").string(), dir);
  EXPECT_EQ(run.rc, 0) << run.err;
}

}  // namespace
}  // namespace packsim
