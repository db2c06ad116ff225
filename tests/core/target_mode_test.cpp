// Target mode (bms.firmware.target: cortex-m4): the example firmware's unchanged C
// source cross-compiled for the Cortex-M4 and run by the virtual MCU against the
// simulated pack. Independent expectations: host mode's decisions on the same
// scenarios, the ELF header of an x86-64 library, the configured budget and watchdog.
// Skipped (with the reason) only when arm-none-eabi-gcc was not found at configure time.
#include <gtest/gtest.h>
#include <hdf5.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "core/firmware/cycle_model.hpp"
#include "core/firmware/elf_image.hpp"
#include "core/firmware/emulator_libraries.hpp"
#include "core/firmware/target_nvic.hpp"
#include "core/io/hdf5_writer.hpp"
#include "core/sim/firmware_failure.hpp"
#include "core/sim/simulation.hpp"
#include "test_support.hpp"

namespace packsim {
namespace {

namespace fs = std::filesystem;

#ifdef PACKSIM_TARGET_ELF_DIR
#define REQUIRE_ARM_TOOLCHAIN()
const std::string kElfDir = PACKSIM_TARGET_ELF_DIR;
#else
#define REQUIRE_ARM_TOOLCHAIN() GTEST_SKIP() << "arm-none-eabi-gcc was not found when packsim was configured: no target ELF"
const std::string kElfDir;
#endif

#ifdef PACKSIM_TARGET_FAULT_FW
#define PACKSIM_TARGET_FAULT_FW_OR_EMPTY PACKSIM_TARGET_FAULT_FW
#else
#define PACKSIM_TARGET_FAULT_FW_OR_EMPTY ""
#endif
#ifdef PACKSIM_TARGET_IRQ_FW
#define PACKSIM_TARGET_IRQ_FW_OR_EMPTY PACKSIM_TARGET_IRQ_FW
#define PACKSIM_TARGET_CAN_FW_OR_EMPTY PACKSIM_TARGET_CAN_FW
#else
#define PACKSIM_TARGET_IRQ_FW_OR_EMPTY ""
#define PACKSIM_TARGET_CAN_FW_OR_EMPTY ""
#endif

std::string exampleElf() { return kElfDir + "/packsim_example_bms_cm4.elf"; }
std::string watchdogElf() { return kElfDir + "/packsim_watchdog_demo_cm4.elf"; }

Scenario bundled(const std::string& name) {
  return loadScenarioFile(test::scenarioDir() + "/firmware/" + name + ".yaml");
}

// The example firmware in target mode trips for the same reason as in host mode, at
// the same time to within one 10 ms tick (its decisions are the same code's; the clock
// differs only by the code's own cycles, which host mode does not count).
void expectSameDecisions(const std::string& name) {
  const RunResult host = runScenario(bundled(name));
  const RunResult target = runScenario(bundled("target/" + name + "_cm4"));
  ASSERT_TRUE(host.summary.tripped) << name;
  ASSERT_TRUE(target.summary.tripped) << name << ": " << target.summary.firmware_status;
  EXPECT_EQ(target.summary.trip_reason, host.summary.trip_reason) << name;
  EXPECT_NEAR(target.summary.trip_time_s, host.summary.trip_time_s, 0.010 + 1e-9) << name;
  EXPECT_NE(target.summary.firmware_status.find("example_bms 1.0: ran to the end"), std::string::npos)
      << target.summary.firmware_status;
  ASSERT_FALSE(target.summary.firmware_target.empty());
}

TEST(TargetMode, TheExampleFirmwareTripsAsInHostModeOnOverCurrent) {
  REQUIRE_ARM_TOOLCHAIN();
  expectSameDecisions("c_example_firmware_overcurrent");
}

TEST(TargetMode, TheExampleFirmwareTripsAsInHostModeOnASilentDevice) {
  REQUIRE_ARM_TOOLCHAIN();
  expectSameDecisions("c_example_firmware_device_silent");
}

TEST(TargetMode, TheExampleFirmwareTripsAsInHostModeOnTheESwitch) {
  REQUIRE_ARM_TOOLCHAIN();
  expectSameDecisions("c_example_firmware_estop");
}

// Outputs act at the MCU clock's instant of the write. The example's 10 ms task reads
// the current, finds it over the limit, opens the relay and then sends its trip event:
// in host mode its code takes no time and no bus transaction comes first, so the
// contact opens at the task's due time, the trip's instant; in target mode it opens
// after the cycles the code ran before the write: later than in host mode, no later
// than the trip event sent after it, and within microseconds at 168 MHz.
TEST(TargetMode, TheRelayOpensAtTheCycleTheCodeWroteIt) {
  REQUIRE_ARM_TOOLCHAIN();
  const RunResult host = runScenario(bundled("c_example_firmware_overcurrent"));
  const RunResult target = runScenario(bundled("target/c_example_firmware_overcurrent_cm4"));
  const double hostOpen_s = test::eventTime(host, "relay_contact", "opened");
  const double targetOpen_s = test::eventTime(target, "relay_contact", "opened");
  ASSERT_TRUE(host.summary.tripped && target.summary.tripped);
  EXPECT_NEAR(hostOpen_s, host.summary.trip_time_s, 1e-9);
  EXPECT_NEAR(hostOpen_s, 60.2, 1e-9);  // on the 10 ms task's due time
  EXPECT_GT(targetOpen_s, hostOpen_s + 1e-8) << "at least a couple of cycles";
  EXPECT_LE(targetOpen_s, target.summary.trip_time_s + 1e-12);
  EXPECT_LT(targetOpen_s, hostOpen_s + 20e-6);
}

// The counts are the emulator's, block by block: the same run gives the same numbers.
TEST(TargetMode, InstructionAndCycleCountsAreDeterministic) {
  REQUIRE_ARM_TOOLCHAIN();
  const Scenario s = bundled("target/c_example_firmware_estop_cm4");
  const RunResult a = runScenario(s), b = runScenario(s);
  EXPECT_EQ(a.summary.firmware_target, b.summary.firmware_target);
  ASSERT_EQ(a.events.size(), b.events.size());
  for (size_t i = 0; i < a.events.size(); ++i) {
    EXPECT_EQ(a.events[i].time_s, b.events[i].time_s) << a.events[i].detail;
    EXPECT_EQ(a.events[i].detail, b.events[i].detail);
  }
  // Both tasks ran, with code in them: instructions and cycles per task, a stack.
  // 40 s (10 s past the 30 s trip): a call every 10 ms, one every 100 ms.
  const std::string& task0 = a.summary.firmware_target.at(0);
  EXPECT_EQ(task0.rfind("task 0 (period 10 ms): 400", 0), 0u) << task0;
  EXPECT_EQ(a.summary.firmware_target.at(1).rfind("task 1 (period 100 ms): 400 calls", 0), 0u)
      << a.summary.firmware_target.at(1);
  EXPECT_NE(a.summary.firmware_target.back().find("cortex-m4 at 168 MHz"), std::string::npos);
}

double summaryAttr(const std::string& file, const std::string& name) {
  double v = -1.0;
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  const hid_t g = H5Gopen2(f, "/summary", H5P_DEFAULT);
  if (H5Aexists(g, name.c_str()) > 0) {
    const hid_t a = H5Aopen(g, name.c_str(), H5P_DEFAULT);
    H5Aread(a, H5T_NATIVE_DOUBLE, &v);
    H5Aclose(a);
  }
  H5Gclose(g);
  H5Fclose(f);
  return v;
}

// The summary's figures are in the result file too, as /summary attributes (only in
// target mode: a host-mode file has none).
TEST(TargetMode, TheFiguresAreSummaryAttributesOfTheResultFile) {
  REQUIRE_ARM_TOOLCHAIN();
  const Scenario s = bundled("target/c_example_firmware_overcurrent_cm4");
  const RunResult r = runScenario(s);
  const std::string file = (test::processTempDir("target_mode") / "r.h5").string();
  writeResultHdf5(file, s, r);
  // task 0's worst call as the summary line prints it
  const std::string& line = r.summary.firmware_target.at(0);
  const size_t at = line.find("instructions / ", line.find("worst ")) + 15;
  const double worst = std::stod(line.substr(at));
  EXPECT_GT(worst, 0.0);
  EXPECT_EQ(summaryAttr(file, "target_task0_worst_cycles"), worst) << line;
  EXPECT_EQ(summaryAttr(file, "target_clock_hz"), 168e6);
  const double cycles = summaryAttr(file, "target_cycles");
  EXPECT_GE(cycles, summaryAttr(file, "target_cycles_trm_min"));
  EXPECT_LE(cycles, summaryAttr(file, "target_cycles_trm_max"));
  EXPECT_NEAR(summaryAttr(file, "target_cpu_load"), cycles / (168e6 * r.summary.duration_s), 1e-6);
  const Scenario host = bundled("c_example_firmware_overcurrent");
  writeResultHdf5(file, host, runScenario(host));
  EXPECT_EQ(summaryAttr(file, "target_cycles"), -1.0);  // absent
}

// The demo firmware hangs at its task on its first boot (hang_at_ms): with a watchdog
// longer than the task's 100 ms budget, the budget stops it, the same contract break
// as in host mode, now counting the code's cycles; a failed run.
TEST(TargetMode, AFirmwareThatLoopsForeverIsStoppedByItsBudget) {
  REQUIRE_ARM_TOOLCHAIN();
  const Scenario s = test::scenarioFromYaml(
      "extends: bench_6s_ncr18650_2C.yaml\n"
      "bms: {tick_ms: 10, firmware: {target: cortex-m4, elf: " + watchdogElf() +
      ", config: {hang_at_ms: 200, watchdog_timeout_us: 5000000}}}\n"
      "run: {duration_s: 1}\n");
  const RunResult r = runScenario(s);
  const double t = test::eventTime(r, "firmware_fault", "contract break in task 0 (period 10 ms): ran 100.0");
  EXPECT_NEAR(t, 0.2, 1e-9);
  const std::string failure = firmwareFailure(s, r);
  EXPECT_NE(failure.find("its code on the MCU clock"), std::string::npos) << failure;
  EXPECT_NE(failure.find("over its 100.000 ms budget"), std::string::npos) << failure;
  EXPECT_EQ(test::eventTime(r, "mcu_reset"), -1.0);
}

// The same hang with a 30 ms watchdog: no kick, the MCU resets at 30 ms after the last
// kick, boots again at the next tick (the .noinit counter says "boot 1"), and closes
// the relay again; the run is not a failure.
TEST(TargetMode, AMissedWatchdogKickResetsTheMcuWhichRecovers) {
  REQUIRE_ARM_TOOLCHAIN();
  const Scenario s = bundled("target/c_watchdog_reset_cm4");
  const RunResult r = runScenario(s);
  const double hang_s = test::eventTime(r, "firmware", "hanging");
  const double reset_s = test::eventTime(r, "mcu_reset", "watchdog: not kicked for 30.000 ms");
  const double boot1_s = test::eventTime(r, "firmware", "boot 1 after 1 watchdog resets");
  // The NVM page (contract v3) kept the first boot's count across the reset.
  EXPECT_GE(test::eventTime(r, "firmware", "boot 0 after 0 watchdog resets; NVM counts 0 boots before"), 0.0);
  EXPECT_NEAR(test::eventTime(r, "firmware", "boot 1 after 1 watchdog resets; NVM counts 1 boots before"), boot1_s, 1e-12);
  ASSERT_NEAR(hang_s, 5.0, 1e-6);
  // The last kick: the end of the task at 4.99 s (its code's few microseconds after it).
  EXPECT_GT(reset_s, 4.99 + 0.030);
  EXPECT_LT(reset_s, 4.99 + 0.030 + 0.001);
  EXPECT_GT(boot1_s, reset_s);
  EXPECT_LT(boot1_s, reset_s + 0.010 + 1e-6);  // the next tick
  EXPECT_EQ(test::eventTime(r, "firmware_fault"), -1.0);
  EXPECT_EQ(firmwareFailure(s, r), "");
  // The relay dropped at the reset and closed again after the second boot.
  // It opens at the reset's instant (the outputs drop there), inside the 5.02 s tick.
  const double opened_s = test::eventTime(r, "relay_contact", "opened");
  EXPECT_NEAR(opened_s, reset_s, 1e-9);
  bool reclosed = false;
  for (const Event& e : r.events)
    if (e.kind == "relay_contact" && e.detail.rfind("closed", 0) == 0 && e.time_s > opened_s) reclosed = true;
  EXPECT_TRUE(reclosed);
  EXPECT_NE(r.summary.firmware_target.back().find("1 watchdog resets"), std::string::npos)
      << r.summary.firmware_target.back();
}

// A brown-out in target mode: the same reset and boot as host mode (the 300 s tick,
// the boot at 300.5 s, the relay again at 300.91 s), RAM reloaded from the ELF, and the
// same SOC resumed from the NVM page: the same code on the same readings (IEEE double
// arithmetic on both; the code's cycles move no 10 ms task across a millisecond).
// Not a watchdog reset: the target line counts none.
TEST(TargetMode, ABrownOutResetsTheMcuAsInHostModeAndTheNvmKeepsTheSoc) {
  REQUIRE_ARM_TOOLCHAIN();
  const RunResult host = runScenario(bundled("c_example_firmware_brownout"));
  const RunResult target = runScenario(bundled("target/c_example_firmware_brownout_cm4"));
  const std::string cause = "brown-out: the 12 V supply at 0.00 V, below the MCU's 4.00 V brown-out threshold";
  EXPECT_NEAR(test::eventTime(target, "mcu_reset", cause), 300.0, 1e-9);
  EXPECT_NE(test::eventTime(target, "mcu_reset", cause + "; held in reset with its outputs off until the supply "
                                                         "recovers, then RAM reloaded from the ELF except .noinit"),
            -1.0);
  std::string hostBoot, targetBoot;
  for (const Event& e : host.events)
    if (e.kind == "firmware" && e.detail.rfind("boot 1:", 0) == 0) hostBoot = e.detail;
  for (const Event& e : target.events)
    if (e.kind == "firmware" && e.detail.rfind("boot 1:", 0) == 0) targetBoot = e.detail;
  ASSERT_EQ(hostBoot.rfind("boot 1: SOC ", 0), 0u) << hostBoot;
  EXPECT_EQ(targetBoot, hostBoot);
  double relay = -1.0;
  for (const Event& e : target.events)
    if (e.kind == "firmware" && e.detail == "relay closed" && e.time_s > 300.0 && relay < 0) relay = e.time_s;
  EXPECT_GT(relay, 300.91);
  EXPECT_LT(relay, 300.91 + 20e-6);  // the code's microseconds at 168 MHz
  EXPECT_FALSE(target.summary.tripped);
  EXPECT_NE(target.summary.firmware_target.back().find(" 0 watchdog resets"), std::string::npos)
      << target.summary.firmware_target.back();
}

// A fault on the MCU ends the call: a firmware_fault with the reason and the PC (in
// the task's code, in flash), and a failed run, as a crash in host mode.
std::string faultOf(int mode) {
  const Scenario s = test::scenarioFromYaml(
      "extends: bench_6s_ncr18650_2C.yaml\n"
      "bms: {tick_ms: 10, firmware: {target: cortex-m4, elf: " PACKSIM_TARGET_FAULT_FW_OR_EMPTY
      ", config: {mode: " + std::to_string(mode) + ", at_ms: 300}}}\n"
      "run: {duration_s: 1}\n");
  const RunResult r = runScenario(s);
  EXPECT_NEAR(test::eventTime(r, "firmware_fault"), 0.3, 1e-6);
  return firmwareFailure(s, r);
}

TEST(TargetMode, AFaultOnTheMcuIsAFirmwareFailureWithItsPc) {
  REQUIRE_ARM_TOOLCHAIN();
  const std::string nullWrite = faultOf(0);
  EXPECT_NE(nullWrite.find("the firmware ELF '" PACKSIM_TARGET_FAULT_FW_OR_EMPTY "' failed at 0.300 s: fault in task 0 "
                           "(period 10 ms): write to unmapped memory: 4 bytes at 0x00000000, PC 0x080"),
            std::string::npos)
      << nullWrite;
  const std::string udf = faultOf(1);
  EXPECT_NE(udf.find("fault in task 0 (period 10 ms): undefined instruction (UsageFault: UNDEFINSTR) at PC 0x080"), std::string::npos) << udf;
  const std::string flashRx = faultOf(2);
  EXPECT_NE(flashRx.find("bus_transfer's rx buffer at 0x080"), std::string::npos) << flashRx;
  EXPECT_NE(flashRx.find("is not in the MCU's RAM"), std::string::npos) << flashRx;
  // 13 levels of 1 KiB past the 8 KiB stack: found by the stack paint when the call returns.
  const std::string overflow = faultOf(3);
  EXPECT_NE(overflow.find("stack overflow in task 0 (period 10 ms): the call used all 8192 bytes of the stack"),
            std::string::npos)
      << overflow;
}

// A task that fills 4 KiB of its stack and then faults never returns: its stack counts
// in the run's high-water all the same. Before, only calls that returned were scanned,
// and the summary said the firmware had used the few hundred bytes of its healthy calls.
TEST(TargetMode, AFaultingCallsStackCountsInTheHighWater) {
  REQUIRE_ARM_TOOLCHAIN();
  const Scenario s = test::scenarioFromYaml(
      "extends: bench_6s_ncr18650_2C.yaml\n"
      "bms: {tick_ms: 10, firmware: {target: cortex-m4, elf: " PACKSIM_TARGET_FAULT_FW_OR_EMPTY
      ", config: {mode: 4, at_ms: 300}}}\n"
      "run: {duration_s: 0.5}\n");
  const RunResult r = runScenario(s);
  EXPECT_NE(firmwareFailure(s, r).find("fault in task 0 (period 10 ms): write to unmapped memory"), std::string::npos);
  double highWater = -1.0;
  for (const auto& [name, value] : r.summary.firmware_target_figures)
    if (name == "target_stack_high_water_bytes") highWater = value;
  EXPECT_GE(highWater, 4096.0);  // the block alone
  EXPECT_LT(highWater, 8192.0);  // within the stack: no overflow
}

// The cost model on single Thumb-2 instructions (hand-assembled, little-endian
// halfwords) against the Cortex-M4 TRM's cycle table: the model's figure and the
// table's range. Needs no toolchain.
TEST(TargetCycleModel, EachInstructionClassCostsWhatTheTableSays) {
  const CycleModel model;
  struct Case {
    const char* what;
    std::vector<uint16_t> halfwords;
    uint32_t cycles, min, max;
  };
  const Case cases[] = {
      {"movs r0, #1", {0x2001}, 1, 1, 1},
      {"ldr r0, [r1]", {0x6808}, 2, 1, 2},             // 2; 1 when pipelined with a neighbour
      {"str r0, [r1]", {0x6008}, 2, 1, 2},
      {"ldrd r0, r1, [r2]", {0xE9D2, 0x0100}, 3, 2, 3},
      {"push {r4-r7, lr}", {0xB5F0}, 6, 6, 6},         // 1 + N
      {"pop {r4, pc}", {0xBD10}, 3, 3, 3},             // 1 + N (the refill is the block transition's)
      {"sdiv r0, r1, r2", {0xFB91, 0xF0F2}, 7, 2, 12},
      {"vdiv.f32 s0, s1, s2", {0xEE80, 0x0A81}, 14, 14, 14},
      {"muls r0, r1, r0", {0x4348}, 1, 1, 1},
  };
  for (const Case& c : cases) {
    std::vector<uint8_t> bytes;
    for (uint16_t h : c.halfwords) {
      bytes.push_back(static_cast<uint8_t>(h & 0xFF));
      bytes.push_back(static_cast<uint8_t>(h >> 8));
    }
    const BlockCost b = model.cost(bytes.data(), bytes.size(), 0x08000000);
    EXPECT_EQ(b.instructions, 1u) << c.what;
    EXPECT_EQ(b.cycles, c.cycles) << c.what;
    EXPECT_EQ(b.cyclesMin, c.min) << c.what;
    EXPECT_EQ(b.cyclesMax, c.max) << c.what;
  }
  // A block adds up its instructions.
  const uint8_t block[] = {0x01, 0x20, 0x08, 0x68, 0xF0, 0xB5};  // movs, ldr, push
  const BlockCost b = model.cost(block, sizeof block, 0x08000000);
  EXPECT_EQ(b.instructions, 3u);
  EXPECT_EQ(b.cycles, 1u + 2u + 6u);
}

// Unicorn and Capstone are loaded when target mode first needs them, not linked
// (core/firmware/emulator_libraries.hpp): every function packsim calls resolves in the
// installed versions, and a library that cannot be loaded is named with the reason, the
// scenario setting that needs it and how to install it. Needs no toolchain.
TEST(TargetEmulatorLibraries, EveryFunctionResolvesAndAMissingLibraryIsNamed) {
  const UnicornApi& u = unicorn();
  for (const void* f : {(const void*)u.open, (const void*)u.close, (const void*)u.strerror, (const void*)u.ctl,
                        (const void*)u.mem_map, (const void*)u.mmio_map, (const void*)u.mem_read,
                        (const void*)u.mem_write, (const void*)u.reg_read, (const void*)u.reg_write,
                        (const void*)u.hook_add, (const void*)u.hook_del, (const void*)u.emu_start,
                        (const void*)u.emu_stop})
    EXPECT_NE(f, nullptr);
  EXPECT_STREQ(u.strerror(UC_ERR_NOMEM), "No memory available or memory not present (UC_ERR_NOMEM)");
  const CapstoneApi& c = capstone();
  for (const void* f : {(const void*)c.open, (const void*)c.close, (const void*)c.option, (const void*)c.disasm,
                        (const void*)c.free})
    EXPECT_NE(f, nullptr);
  try {
    openEmulatorLibrary("libpacksim-no-such-emulator.so.9", "the Unicorn engine (the ARM emulator)", "libunicorn2");
    ADD_FAILURE() << "a library that does not exist was loaded";
  } catch (const std::runtime_error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("bms.firmware.target: cortex-m4"), std::string::npos) << m;
    EXPECT_NE(m.find("the Unicorn engine"), std::string::npos) << m;
    EXPECT_NE(m.find("libpacksim-no-such-emulator.so.9, which could not be loaded ("), std::string::npos) << m;
    EXPECT_NE(m.find("cannot open shared object file"), std::string::npos) << m;  // dlerror's reason
    EXPECT_NE(m.find("scripts/install-deps.sh --run"), std::string::npos) << m;
    EXPECT_NE(m.find("libunicorn2"), std::string::npos) << m;
  }
}

// A library built for the host is refused when the scenario loads, naming the file and
// the ELF field; so are a missing file and an ELF without the board's symbols.
TEST(TargetMode, AnElfForAnotherArchitectureOrWithoutTheBoardIsALoadError) {
  REQUIRE_ARM_TOOLCHAIN();
  const std::string base = "extends: bench_6s_ncr18650_2C.yaml\nbms: {firmware: {target: cortex-m4, elf: ";
  const std::string x86 = test::yamlErrorOf(base + PACKSIM_PROBE_FW + "}}\n");
  EXPECT_NE(x86.find("test.yaml:2:"), std::string::npos) << x86;
  EXPECT_NE(x86.find(PACKSIM_PROBE_FW), std::string::npos) << x86;
  EXPECT_NE(x86.find("e_machine: 62 (x86-64)"), std::string::npos) << x86;
  const std::string missing = test::yamlErrorOf(base + "no_such_fw}}\n");
  EXPECT_NE(missing.find("firmware ELF 'no_such_fw' not found"), std::string::npos) << missing;
  EXPECT_NE(missing.find("no_such_fw.elf"), std::string::npos) << missing;
  const fs::path stripped = test::processTempDir("target_mode") / "stripped.elf";
  const std::string cmd = "arm-none-eabi-strip -o " + stripped.string() + " " + exampleElf();
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  const std::string noSyms = test::yamlErrorOf(base + stripped.string() + "}}\n");
  EXPECT_NE(noSyms.find("symbol psbsp_entry: missing"), std::string::npos) << noSyms;
  const std::string wrongTarget = test::yamlErrorOf(
      "extends: bench_6s_ncr18650_2C.yaml\nbms: {firmware: {target: cortex-m7, elf: " + exampleElf() + "}}\n");
  EXPECT_NE(wrongTarget.find("unknown target 'cortex-m7'; allowed: cortex-m4"), std::string::npos) << wrongTarget;
  EXPECT_THROW(readTargetElf(PACKSIM_PROBE_FW), ElfError);
}

// --- interrupts (tests/firmware/target_irq_fw.c) -----------------------------------

// System C's bench pack with the FAULT line out of the relay drive (only the firmware
// opens it), thermistor 1 shorted at 2.05 s: the BQ76PL536A's 65 degC comparator holds
// its 1 s delay and asserts FAULT at the 3.05 s tick.
RunResult irqRun(int alertIrq, int timerPeriodUs, int raceLoops, int raceProtect, double duration_s = 3.5) {
  const Scenario s = test::scenarioFromYaml(
      "extends: bench_6s_ncr18650_2C.yaml\n"
      "hardware: {afe: {fault_line_opens_relay: false}}\n"
      "bms: {tick_ms: 10, firmware: {target: cortex-m4, elf: " PACKSIM_TARGET_IRQ_FW_OR_EMPTY ", config: {alert_irq: " +
      std::to_string(alertIrq) + ", timer_period_us: " + std::to_string(timerPeriodUs) +
      ", report_at_ms: 500, race_at_ms: 700, race_loops: " + std::to_string(raceLoops) +
      ", race_protect: " + std::to_string(raceProtect) + "}}}\n"
      "faults: [{kind: thermistor_short, thermistor: 1, at_s: 2.05}]\n"
      "run: {duration_s: " + std::to_string(duration_s) + "}\n");
  return runScenario(s);
}

std::string irqLine(const RunResult& r, const std::string& start) {
  for (const std::string& l : r.summary.firmware_target)
    if (l.rfind(start, 0) == 0) return l;
  return "";
}

// The ALERT handler opens the relay at the line's edge plus its own cycles, counted by
// hand from the cycle model's table (the handler is assembly: target_irq_fw.c): 12 to
// enter, 8 for its block, 2 for the branch into the service stub and 1 for its SVC:
// 23 cycles = 136.9 ns at 168 MHz. Polling the same line in a 100 ms task opens it at
// the task's next run, 3.1 s: 50 ms later.
TEST(TargetInterrupts, TheAlertHandlerOpensTheRelayAtTheEdgePlusItsCycles) {
  REQUIRE_ARM_TOOLCHAIN();
  const RunResult irq = irqRun(1, 0, 0, 0);
  const double edge_s = test::eventTime(irq, "monitor_fault_line", "asserted");
  ASSERT_NEAR(edge_s, 3.05, 1e-9);
  EXPECT_NEAR(test::eventTime(irq, "relay_contact", "opened"), edge_s + 23 / 168e6, 1.5e-9);
  // Its summary line: one call; 34 cycles = the 23 above, the stub's bx lr (1) and the
  // 10-cycle return; entered 12 cycles after the edge (the MCU idled).
  const std::string line = irqLine(irq, "IRQ 0 ALERT: ");
  EXPECT_EQ(line.rfind("IRQ 0 ALERT: 1 calls, mean 34 cycles, worst 34 cycles", 0), 0u) << line;
  EXPECT_NE(line.find("worst latency 12 cycles = 0.07"), std::string::npos) << line;
  const RunResult poll = irqRun(0, 0, 0, 0);
  EXPECT_NEAR(test::eventTime(poll, "monitor_fault_line", "asserted"), edge_s, 1e-12);
  const double polled_s = test::eventTime(poll, "relay_contact", "opened");
  EXPECT_GT(polled_s, 3.1);
  EXPECT_LT(polled_s, 3.1 + 1e-6);
  EXPECT_EQ(irqLine(poll, "IRQ 0"), "");  // never enabled: no handler ran
}

// The board timer interrupts every period from the instant init started it (a few
// microseconds after 0): by 500 ms, floor((500 ms - start) / period) calls: 1666 at
// 300 us (not a multiple of the 10 ms tick: its instants fall inside ticks), 499 at 1 ms.
TEST(TargetInterrupts, ATimerInterruptCountsItsPeriodsExactly) {
  REQUIRE_ARM_TOOLCHAIN();
  EXPECT_GE(test::eventTime(irqRun(1, 300, 0, 0, 0.6), "firmware", "timer 1666 calls, count 1666"), 0.5);
  EXPECT_GE(test::eventTime(irqRun(1, 1000, 0, 0, 0.6), "firmware", "timer 499 calls, count 499"), 0.5);
}

// A 300 us timer pre-empts a task that runs a read-modify-write loop for milliseconds on
// a variable the handler increments too: the handler runs while the task is mid-loop,
// and every call that lands between the task's load and store loses an update. The
// loop's 48-nop block holds the window: the interrupt is taken inside it, at the
// instruction boundary its instant reaches (latency 12 cycles + at most one
// instruction), not at the block's end. With the read-modify-write in a critical section
// (PRIMASK) no update is lost; the timer waits for the section's end.
TEST(TargetInterrupts, AHandlerPreemptsALongTaskMidLoopAndRacesIt) {
  REQUIRE_ARM_TOOLCHAIN();
  const auto race = [](const RunResult& r, unsigned& calls, unsigned& first, unsigned& lost) {
    for (const Event& e : r.events)
      if (e.kind == "firmware" && e.detail.rfind("race: ", 0) == 0)
        return std::sscanf(e.detail.c_str(), "race: 10000 loops, %u handler calls during them, the first at loop %u, %u updates lost",
                           &calls, &first, &lost) == 3;
    return false;
  };
  unsigned calls = 0, first = 0, lost = 0;
  const RunResult open = irqRun(1, 300, 10000, 0, 0.8);
  ASSERT_TRUE(race(open, calls, first, lost));
  EXPECT_GE(calls, 5u);  // the loop runs milliseconds
  EXPECT_GT(first, 0u);
  EXPECT_LT(first, 10000u);
  EXPECT_GT(lost, 0u);
  EXPECT_LE(lost, calls);
  const std::string timer = irqLine(open, "IRQ 2 timer: ");
  unsigned latency = 999;
  ASSERT_NE(timer.find("worst latency "), std::string::npos) << timer;
  std::sscanf(timer.c_str() + timer.find("worst latency "), "worst latency %u cycles", &latency);
  EXPECT_GE(latency, 12u) << timer;
  EXPECT_LE(latency, 12u + 10u) << timer;  // the firmware's longest instruction: a 9-register push or pop
  const RunResult locked = irqRun(1, 300, 10000, 1, 0.8);
  ASSERT_TRUE(race(locked, calls, first, lost));
  EXPECT_GE(calls, 5u);
  EXPECT_EQ(lost, 0u);
}

// An interrupt enabled without a handler (its vector the board's default) is a fault
// naming the handler the firmware lacks.
TEST(TargetInterrupts, AnInterruptWithoutAHandlerIsAFault) {
  REQUIRE_ARM_TOOLCHAIN();
  const RunResult r = irqRun(2, 0, 0, 0, 0.1);
  bool found = false;
  for (const Event& e : r.events)
    found = found || (e.kind == "firmware_fault" &&
                      e.detail.find("interrupt 1 (PSBSP_CAN_RX_IRQHandler) enabled and taken, but the firmware defines "
                                    "no handler for it") != std::string::npos);
  EXPECT_TRUE(found);
}

// The NVIC's choice (no toolchain needed): priorities, masks, PRIGROUP.
TEST(TargetNvic, PrioritiesAndMasksDecideWhichInterruptIsTaken) {
  TargetNvic n(0x08000000);
  n.write(0x400, 0x00402000u, 4);  // IPR: ALERT 0x00, CAN 0x20, timer 0x40
  n.pend(kTargetIrqTimer);
  n.pend(kTargetIrqCanRx);
  EXPECT_EQ(n.next(kThreadPriority), -1);  // pending, not enabled
  n.write(0x100, 0x6u, 4);                 // ISER: CAN, timer
  EXPECT_EQ(n.next(kThreadPriority), kTargetIrqCanRx);  // the higher priority first
  EXPECT_EQ(n.next(n.executionPriority(1, 0, 0)), -1);  // PRIMASK
  EXPECT_EQ(n.next(n.executionPriority(0, 0, 0x20)), -1);  // BASEPRI 0x20 masks 0x20 and 0x40
  EXPECT_EQ(n.next(n.executionPriority(0, 0, 0x30)), kTargetIrqCanRx);
  n.activate(kTargetIrqCanRx);
  EXPECT_EQ(n.next(n.executionPriority(0, 0, 0)), -1);  // the timer (0x40) waits for the CAN handler (0x20)
  n.pend(kTargetIrqAlert);
  n.write(0x100, 0x1u, 4);
  EXPECT_EQ(n.next(n.executionPriority(0, 0, 0)), kTargetIrqAlert);  // 0x00 pre-empts it (nesting)
  n.deactivate(kTargetIrqCanRx);
  // PRIGROUP 5: bits [7:6] group, [5:0] sub: 0x20 and 0x00 are one group, no pre-emption.
  n.write(0xD0C, 0x05FA0500u, 4);
  n.activate(kTargetIrqCanRx);
  EXPECT_EQ(n.next(n.executionPriority(0, 0, 0)), -1);
  EXPECT_EQ(n.read(0xD0C, 0) & 0x700u, 0x500u);
  EXPECT_EQ(n.read(0x300, 0), 0x2u);  // IABR: CAN active
  n.write(0x180, 0x7u, 4);            // ICER
  EXPECT_EQ(n.read(0x100, 0), 0u);
}

// --- CAN for a board alone (hardware.can; tests/firmware/can_fw.c) --------------------

// The vehicle sends 0x200 (no data) at 0.25, 0.35, 0.45 s and 0x123 [11 22] at 0.5005 s;
// the firmware echoes each with id + 1 and sends 0x180 [counter] every 100 ms.
Scenario canScenario(const std::string& firmware, int useIrq) {
  return test::scenarioFromYaml(
      "extends: bench_6s_ncr18650_2C.yaml\n"
      "hardware:\n"
      "  can:\n"
      "    bitrate_kbps: 500\n"
      "    frames:\n"
      "      - {at_s: 0.5005, id: 0x123, data: [0x11, 0x22]}\n"
      "      - {at_s: 0.25, id: 0x200, data: [], period_s: 0.1, until_s: 0.45}\n"
      "bms: {tick_ms: 10, firmware: {" + firmware + ", config: {use_irq: " + std::to_string(useIrq) + "}}}\n"
      "run: {duration_s: 0.8}\n");
}

RunResult canRun(const std::string& firmware, int useIrq) { return runScenario(canScenario(firmware, useIrq)); }

// When the firmware read 0x123 (its "rx" event's "at N us").
long rxAt_us(const RunResult& r, const std::string& what) {
  for (const Event& e : r.events)
    if (e.kind == "firmware" && e.detail.rfind("rx " + what, 0) == 0)
      return std::stol(e.detail.substr(e.detail.find(" at ") + 4));
  return -1;
}

// The scripted frames go on the idle bus at their instant and take their stuffed bit
// count at 500 kbit/s (0 bytes: 47 bits + at most 8 stuff bits; 2 bytes: 63 + at most
// 12); what the firmware sent is in the trace, frame for frame, as its own "tx" events
// list it.
void expectTraceOf(const RunResult& r) {
  std::vector<std::string> sent, traced;
  for (const Event& e : r.events)
    if (e.kind == "firmware" && e.detail.rfind("tx ", 0) == 0) sent.push_back(e.detail);
  int in = 0;
  for (const CanTraceRow& row : r.can_trace) {
    char head[40];
    std::snprintf(head, sizeof head, "tx 0x%03X [%d]", row.id, row.dlc);
    if (row.out) {
      traced.push_back(std::string(head) + (row.data.empty() ? "" : " " + row.data));
      continue;
    }
    ++in;
    const double bits = (row.end_s - row.time_s) * 500e3;
    if (row.id == 0x123) {
      EXPECT_NEAR(row.time_s, 0.5005, 1e-12);
      EXPECT_EQ(row.data, "11 22");
      EXPECT_GE(bits, 63 - 1e-6);
      EXPECT_LE(bits, 75 + 1e-6);
    } else {
      EXPECT_EQ(row.id, 0x200);
      EXPECT_GE(bits, 47 - 1e-6);
      EXPECT_LE(bits, 55 + 1e-6);
    }
    EXPECT_FALSE(row.lost);
  }
  EXPECT_EQ(in, 4);
  EXPECT_GE(sent.size(), 10u);  // 7 status frames by 0.7 s, 4 echoes
  EXPECT_EQ(traced, sent);
}

double frameEnd(const RunResult& r, int id) {
  for (const CanTraceRow& row : r.can_trace)
    if (!row.out && row.id == id) return row.end_s;
  return -1.0;
}

// Host mode: the 1 ms task reads 0x123 at its first run after the frame's end.
TEST(CanAlone, AFirmwareReceivesTheScriptedFramesAndItsFramesAreRecorded) {
  const RunResult r = canRun("library: " PACKSIM_CAN_FW, 0);
  const double end = frameEnd(r, 0x123);
  ASSERT_GT(end, 0.5005);
  EXPECT_EQ(rxAt_us(r, "0x123 [2] 11 22"), static_cast<long>(std::ceil(end * 1e3)) * 1000);
  expectTraceOf(r);
  // The result file's /can_trace holds the same rows.
  const std::string file = (test::processTempDir("target_mode") / "can.h5").string();
  writeResultHdf5(file, canScenario("library: " PACKSIM_CAN_FW, 0), r);
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  const hid_t ds = H5Dopen2(f, "/can_trace", H5P_DEFAULT);
  const hid_t space = H5Dget_space(ds);
  hsize_t rows = 0;
  H5Sget_simple_extent_dims(space, &rows, nullptr);
  H5Sclose(space);
  H5Dclose(ds);
  H5Fclose(f);
  EXPECT_EQ(rows, r.can_trace.size());
}

// Target mode: the same, polled (a few microseconds of code later), and by the CAN
// receive interrupt: its handler reads the frame microseconds after its end, before the
// poll would have, entered 12 cycles after it arrived.
TEST(CanAlone, TargetModeReceivesByPollingAndByTheReceiveInterrupt) {
  REQUIRE_ARM_TOOLCHAIN();
  const RunResult polled = canRun("target: cortex-m4, elf: " PACKSIM_TARGET_CAN_FW_OR_EMPTY, 0);
  const double end = frameEnd(polled, 0x123);
  const long poll_us = static_cast<long>(std::ceil(end * 1e3)) * 1000;
  EXPECT_GE(rxAt_us(polled, "0x123 [2] 11 22"), poll_us);
  EXPECT_LT(rxAt_us(polled, "0x123 [2] 11 22"), poll_us + 100);
  expectTraceOf(polled);
  const RunResult irq = canRun("target: cortex-m4, elf: " PACKSIM_TARGET_CAN_FW_OR_EMPTY, 1);
  EXPECT_NEAR(frameEnd(irq, 0x123), end, 1e-12);
  const long at = rxAt_us(irq, "0x123 [2] 11 22");
  EXPECT_GE(at, static_cast<long>(end * 1e6));
  EXPECT_LT(at, static_cast<long>(end * 1e6) + 100);
  EXPECT_LT(at, poll_us);
  expectTraceOf(irq);
  const std::string line = irqLine(irq, "IRQ 1 CAN receive: ");
  EXPECT_EQ(line.rfind("IRQ 1 CAN receive: 4 calls", 0), 0u) << line;
  EXPECT_NE(line.find("worst latency 12 cycles"), std::string::npos) << line;
}

// Bad frames are errors at their line, naming the field and the allowed range.
TEST(CanAlone, BadScriptedFramesAreLoadErrors) {
  const std::string base = "extends: bench_6s_ncr18650_2C.yaml\nhardware:\n  can:\n    frames:\n";
  const std::string id = test::yamlErrorOf(base + "      - {at_s: 1, id: 0x800}\n");
  EXPECT_NE(id.find("test.yaml:5:"), std::string::npos) << id;
  EXPECT_NE(id.find("hardware.can.frames[0].id: 0x800 is out of range; allowed [0, 2047] (0x7FF)"), std::string::npos) << id;
  const std::string nine = test::yamlErrorOf(base + "      - {at_s: 1, id: 1, data: [1,2,3,4,5,6,7,8,9]}\n");
  EXPECT_NE(nine.find("9 bytes: a classic CAN data frame carries at most 8"), std::string::npos) << nine;
  const std::string byte = test::yamlErrorOf(base + "      - {at_s: 1, id: 1, data: [256]}\n");
  EXPECT_NE(byte.find("hardware.can.frames[0].data[0]: 256 is out of range; allowed [0, 255]"), std::string::npos) << byte;
  const std::string word = test::yamlErrorOf(base + "      - {at_s: 1, id: one}\n");
  EXPECT_NE(word.find("expected a whole number (decimal or 0x hex), got 'one'"), std::string::npos) << word;
  const std::string period = test::yamlErrorOf(base + "      - {at_s: 1, id: 1, until_s: 2}\n");
  EXPECT_NE(period.find("until_s needs a period_s"), std::string::npos) << period;
  const std::string boards = test::yamlErrorOf(
      "extends: motorcycle_110s.yaml\nhardware:\n  afe: {devices_per_board: 5}\n  can:\n    frames: [{at_s: 1, id: 1}]\n");
  EXPECT_NE(boards.find("scripted frames need a board alone"), std::string::npos) << boards;
}

}  // namespace
}  // namespace packsim
