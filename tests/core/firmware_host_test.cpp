// The firmware host against tiny test firmwares (tests/firmware/probe_fw.c,
// abi_mismatch_fw.c) on a fake monitor chain: the scheduler's periods and order, the
// clock advancing with bus time, and every way a firmware can fail without taking the
// simulator down.
#include <gtest/gtest.h>

#include <cmath>
#include <csignal>
#include <random>
#include <sstream>

#include "core/firmware/clock_ns.hpp"
#include "core/firmware/firmware_host.hpp"

namespace packsim {
namespace {

// One device that answers every transaction with rxLen bytes of 0xA5 after 250 µs.
class FakeChain : public MonitorChain {
 public:
  FakeChain() { analog_.cell_V.assign(6, 3.7); }
  int deviceCount() const override { return 1; }
  int cellsOf(int) const override { return 6; }
  DeviceAnalog& analog(int) override { return analog_; }
  void setCommFault(int, const MonitorDeviceFault&) override {}
  void setBrokenLinkAbove(int) override {}
  void advance(double t) override { advancedTo.push_back(t); }
  BusTransfer transfer(double t, const uint8_t*, size_t, uint8_t* rx, size_t rxLen) override {
    transfersAt.push_back(t);
    if (silent) return {-1, 250e-6};  // nothing answered
    for (size_t i = 0; i < rxLen; ++i) rx[i] = 0xA5;
    return {static_cast<int>(rxLen), 250e-6};
  }
  bool faultLine() const override { return false; }
  bool balancing(int, int) const override { return false; }

  std::vector<double> advancedTo, transfersAt;
  bool silent = false;

 private:
  DeviceAnalog analog_;
};

struct Log : FirmwareSink {
  void event(double t, const std::string& kind, const std::string& detail) override {
    events.push_back({t, kind, detail});
  }
  void trip(double t, const std::string& reason) override { trips.push_back({t, "trip", reason}); }
  struct E {
    double t;
    std::string kind, detail;
  };
  std::vector<E> events, trips;
  std::vector<std::string> of(const std::string& kind) const {
    std::vector<std::string> v;
    for (const E& e : events)
      if (e.kind == kind) v.push_back(e.detail);
    return v;
  }
};

enum Mode { PROBE, BUS, CRASH, HANG, ABORT, DIV0, INIT_FAIL, BAD_BUS, BIG_RX, BUS_LOOP, TRIP, RETIME, CODES, PIN_TIMING, NVM, BOOTS, TRIP_TEXTS, WIRING };

FirmwareSettings probe(int mode, int at_ms = 0, const char* lib = PACKSIM_PROBE_FW) {
  FirmwareSettings s;
  s.library = true;
  s.library_path = lib;
  s.watchdog_s = 0.2;
  for (int32_t v : {mode, at_ms})
    for (int b = 0; b < 4; ++b) s.config.push_back(static_cast<uint8_t>((static_cast<uint32_t>(v) >> (8 * b)) & 0xFF));
  return s;
}

struct Bench {
  explicit Bench(const FirmwareSettings& s, double tick_s = 0.01)
      : settings(s), host(settings, FirmwareBoard{{&bus}, 2}, tick_s, log) {
    bus.chain = std::make_unique<FakeChain>();
  }
  FakeChain& chain() { return static_cast<FakeChain&>(*bus.chain); }
  void run(int ticks, double tick_s = 0.01) {
    for (int k = 0; k < ticks; ++k) host.step(k * tick_s, in, out);
  }
  FirmwareSettings settings;
  MonitorBus bus;
  Log log;
  FirmwareHost host;
  bms::Inputs in{};
  bms::Outputs out{};
};

// Init at 0, task i first at its period, then every period; tasks due together run
// in declaration order; the 15 ms task (not a multiple of the 10 ms tick) at its own
// due times on its clock.
// The clock's conversion (core/firmware/clock_ns.hpp) against std::llround: tick
// instants and bus durations as the host forms them, exact half-way cases, the values
// next to them, and what falls back to the library (negative, past 2^52 ns, NaN).
TEST(FirmwareHost, TheClocksNanosecondsAreLlroundsToTheBit) {
  const auto ref = [](double t_s) { return static_cast<uint64_t>(std::llround(t_s * 1e9)); };
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  long checked = 0;
  for (long k = 0; k < 200000; ++k) {
    const double tick = static_cast<double>(k) * 0.01;  // the loop's t = k·tick_s
    const double bus = u(rng) * 1e-3 * std::ldexp(1.0, static_cast<int>(u(rng) * 20) - 10);
    for (const double t : {tick, bus, tick + bus, std::nextafter(tick, 0.0), std::nextafter(tick, 1e9)}) {
      ASSERT_EQ(toNs(t), ref(t)) << t;
      ++checked;
    }
  }
  for (long i = 0; i < 100000; ++i) {  // near half-way: (i + 1/2) ns, most products exactly so
    const double t = (static_cast<double>(i) + 0.5) * 1e-9;
    ASSERT_EQ(toNs(t), ref(t)) << i;
  }
  for (const double x : {0.5, 1.5, 2.5, 4503599627370495.5, 0.49999999999999994, 1e15 + 0.5, 4503599627370496.0,
                         1e17, -0.4, -2.5, 0.0, -0.0}) {
    EXPECT_EQ(toNs(x * 1e-9), ref(x * 1e-9)) << x;
    EXPECT_EQ(toNs(std::nextafter(x, 1e30) * 1e-9), ref(std::nextafter(x, 1e30) * 1e-9)) << x;
  }
  EXPECT_EQ(checked, 1000000);
}

TEST(FirmwareHost, RunsEachTaskAtItsPeriodInDeclarationOrder) {
  Bench b(probe(PROBE));
  b.run(7);  // ticks 0..60 ms: instances due in [0, 70) ms
  const std::vector<std::string> expected = {
      "task0 10000", "task2 15000", "task0 20000", "task1 20000", "task0 30000", "task2 30000", "task0 40000",
      "task1 40000", "task2 45000", "task0 50000", "task0 60000", "task1 60000", "task2 60000"};
  EXPECT_EQ(b.log.of("firmware"), expected);
  EXPECT_EQ(b.log.of("config_warning").size(), 1u);  // the 15 ms task
  EXPECT_FALSE(b.host.dead());
  EXPECT_EQ(b.host.taskRuns(0), 6u);
}

// Contract v2: init may set a task's period from its configuration (0: off); a task
// the descriptor lacks, or a call outside init, is refused.
TEST(FirmwareHost, InitSetsTaskPeriodsOnlyDuringInit) {
  Bench b(probe(RETIME));
  b.run(10);  // instances due in [0, 100) ms
  const std::vector<std::string> expected = {"retime 30000 -3", "retime 60000 -3", "retime 90000 -3"};
  EXPECT_EQ(b.log.of("firmware"), expected);
  EXPECT_FALSE(b.host.dead());
  EXPECT_EQ(b.host.taskRuns(2), 0u) << "switched off at init";
  EXPECT_EQ(b.host.taskRuns(1), 4u) << "untouched: 20 ms";
}

TEST(FirmwareHost, BusTransfersAdvanceTheClockByTheirDuration) {
  Bench b(probe(BUS));
  b.run(2);  // task 0 at 10 ms
  ASSERT_EQ(b.log.of("firmware").size(), 1u);
  EXPECT_EQ(b.log.of("firmware")[0], "bus 10000 10250 8");
  ASSERT_EQ(b.chain().transfersAt.size(), 1u);
  EXPECT_DOUBLE_EQ(b.chain().transfersAt[0], 0.010);
  EXPECT_DOUBLE_EQ(b.chain().advancedTo.back(), 0.010);  // the chain caught up with the MCU clock first
}

// Contract v3: a channel the board does not have (an ADC channel, a pin, CAN on a board
// alone) is PSFW_NO_CHANNEL (-3), a bus nobody answers PSFW_BUS_TIMEOUT (-1); the same
// code declaring version 2 still gets -1 for both, as it was built to expect.
TEST(FirmwareHost, AVersion3FirmwareTellsAMissingChannelFromABusTimeout) {
  static_assert(PSFW_NO_CHANNEL != PSFW_BUS_TIMEOUT && PSFW_NO_CHANNEL != PSFW_BUS_ERROR, "distinct codes");
  Bench v3(probe(CODES));
  v3.chain().silent = true;
  v3.run(2);
  EXPECT_EQ(v3.log.of("firmware"), std::vector<std::string>{"codes -3 -3 -3 -3 -1"});
  Bench v2(probe(CODES, 0, PACKSIM_PROBE_FW_V2));
  v2.chain().silent = true;
  v2.run(2);
  EXPECT_EQ(v2.log.of("firmware"), std::vector<std::string>{"codes -1 -1 -1 -1 -1"});
  EXPECT_FALSE(v2.host.dead());
}

// A channel or pin the board does not have still answers PSFW_NO_CHANNEL (a write: does
// nothing), and the run says so once per service and channel, at the first call: the
// probe (WIRING) reads ADC channels 17 (thermistor 1 of the bench's two: wired) and 18,
// input pin 9, writes output pin 7 and DAC channel 3 at every 10 ms run of task 0. Over
// five runs: four events at 10 ms, none for channel 17.
TEST(FirmwareHost, AChannelTheBoardDoesNotHaveIsReportedOncePerChannel) {
  Bench b(probe(WIRING));
  b.in.mcuThermistorCode[1] = 2048;
  b.run(6);
  EXPECT_EQ(b.log.of("firmware"), std::vector<std::string>{"wiring 2048 -3 -3"});
  const std::vector<std::string> expected = {
      "adc_read(channel 18): the board has no such ADC channel (it has 0 current sense, 1 bus voltage, 16-17 the 2 "
      "thermistors on the MCU's ADC); it returned PSFW_NO_CHANNEL (-3), no reading",
      "gpio_read(pin 9): the board has no such input pin (0-6: internal and external E-switch, relay aux, monitor "
      "FAULT, charger present, run request, reset request); it returned PSFW_NO_CHANNEL (-3)",
      "gpio_write(pin 7, 1): the board has no such output pin (0 relay, 1 precharge, 2 discharge FET, 3 charge FET, 4 "
      "charger enable); the write drives nothing",
      "dac_write(channel 3, 500): the board has no such DAC channel (0 charger current, mA); the write drives nothing"};
  EXPECT_EQ(b.log.of("firmware_misuse"), expected);
  EXPECT_EQ(b.host.taskRuns(0), 5u);
  for (const auto& e : b.log.events)
    if (e.kind == "firmware_misuse") EXPECT_DOUBLE_EQ(e.t, 0.010) << e.detail;
  // Version 2 got -1 there, which it shares with a bus timeout: said so.
  Bench v2(probe(WIRING, 0, PACKSIM_PROBE_FW_V2));
  v2.run(2);
  ASSERT_FALSE(v2.log.of("firmware_misuse").empty());
  EXPECT_NE(v2.log.of("firmware_misuse")[0].find("it returned -1 (no such channel in contract versions 1 and 2"),
            std::string::npos)
      << v2.log.of("firmware_misuse")[0];
}

// Contract v3 NVM: erased (0xFF) at the start; a 12-byte write at offset 4 touches the
// 8-byte pages 0 and 1, so it takes 2 x 5 ms of the clock; a read past the 256 bytes is
// PSFW_NO_CHANNEL. The page is the host's: what init wrote is there after the run.
TEST(FirmwareHost, TheNvmPageIsErasedAtTheStartAndAWriteTakesItsPageCycles) {
  Bench b(probe(NVM));
  b.run(1);
  EXPECT_EQ(b.log.of("firmware"), std::vector<std::string>{"nvm 4294967295 0 10000 12 -3"});
  EXPECT_EQ(b.host.nvm()[3], 0xFF);
  EXPECT_EQ(b.host.nvm()[4], 1);
  EXPECT_EQ(b.host.nvm()[15], 12);
  EXPECT_EQ(b.host.nvm()[16], 0xFF);
}

// A brown-out in host mode (holdInReset for the ticks the supply is low): the outputs
// drop to their reset level at the first low tick, nothing runs while it is held,
// and the next step() boots the firmware: init again on zeroed instance RAM (its task
// counter starts over), the NVM page kept (its boot count goes on). The library's
// static variables are not reloaded: its static count goes on too (docs/firmware.md).
TEST(FirmwareHost, ABrownOutResetsTheMcuWhichBootsOnZeroedRamWithItsNvmKept) {
  Bench b(probe(BOOTS));
  b.run(3);  // init at 0, task 0 at 10 and 20 ms
  ASSERT_EQ(b.log.of("firmware").size(), 3u);
  const std::string first = b.log.of("firmware")[0];
  ASSERT_EQ(first.rfind("boot 0 static ", 0), 0u) << first;
  EXPECT_EQ(b.log.of("firmware")[2], "ram 2");
  EXPECT_TRUE(b.out.relayClose && b.out.dischargeFetOn && b.out.chargeFetOn);
  b.host.takePinChanges();

  b.host.holdInReset(0.030, "brown-out: test", b.out);
  b.host.holdInReset(0.040, "brown-out: test", b.out);  // still low: no second reset
  EXPECT_FALSE(b.out.relayClose || b.out.prechargeClose || b.out.dischargeFetOn || b.out.chargeFetOn ||
               b.out.chargerEnable);
  EXPECT_EQ(b.out.chargerCurrentRequest_mA, 0);
  const std::vector<PinChange> drop = b.host.takePinChanges();
  ASSERT_EQ(drop.size(), 1u);
  EXPECT_DOUBLE_EQ(drop[0].t_s, 0.030);
  EXPECT_TRUE(drop[0].pins == PinLevels{});
  ASSERT_EQ(b.log.of("mcu_reset").size(), 1u);
  EXPECT_EQ(b.log.of("mcu_reset")[0].rfind("brown-out: test; held in reset", 0), 0u) << b.log.of("mcu_reset")[0];
  EXPECT_NE(b.log.of("mcu_reset")[0].find("the instance RAM zeroed"), std::string::npos);
  EXPECT_EQ(b.log.of("firmware").size(), 3u) << "no call while held in reset";
  EXPECT_TRUE(b.host.heldInReset());
  EXPECT_EQ(b.host.resets(), 1u);

  for (int k = 5; k < 7; ++k) b.host.step(k * 0.01, b.in, b.out);  // the supply is back at 50 ms
  const std::vector<std::string> fw = b.log.of("firmware");
  ASSERT_EQ(fw.size(), 5u);
  const unsigned long static0 = std::stoul(first.substr(first.find("static ") + 7));
  EXPECT_EQ(fw[3], "boot 1 static " + std::to_string(static0 + 1) + " ram 0");  // NVM kept, RAM zeroed, statics kept
  EXPECT_EQ(fw[4], "ram 1");                    // task 0 at 60 ms: one period after the boot at 50 ms
  EXPECT_EQ(b.log.of("firmware_loaded").size(), 2u);
  EXPECT_EQ(b.host.nvm()[0], 2);
  EXPECT_TRUE(b.out.relayClose) << "init closed it again";
  EXPECT_FALSE(b.host.dead());
}

TEST(FirmwareHost, AnAbiMismatchIsAFirmwareFault) {
  Bench b(probe(PROBE, 0, PACKSIM_ABI_MISMATCH_FW));
  b.run(3);
  ASSERT_TRUE(b.host.dead());
  EXPECT_NE(b.host.faultCause().find("ABI mismatch"), std::string::npos) << b.host.faultCause();
  EXPECT_EQ(b.log.of("firmware_fault").size(), 1u);
}

TEST(FirmwareHost, InitReturningNonZeroIsAFirmwareFault) {
  Bench b(probe(INIT_FAIL));
  b.run(3);
  ASSERT_TRUE(b.host.dead());
  EXPECT_EQ(b.host.faultCause(), "init returned 7 (not 0)");
  EXPECT_EQ(b.host.taskRuns(0), 0u);
}

TEST(FirmwareHost, AMissingLibraryIsAFirmwareFaultNotACrash) {
  Bench b(probe(PROBE, 0, "/nonexistent/libfw.so"));
  b.run(2);
  ASSERT_TRUE(b.host.dead());
  EXPECT_NE(b.host.faultCause().find("cannot load /nonexistent/libfw.so"), std::string::npos);
}

// A dead MCU: one firmware_fault, no further calls, the pins it drove hold their level.
// The fault is at the instant the call failed: `ran_s` after the call's start at at_ms
// for a call that ran past its budget (it was timed at the call's start).
void expectDeadAfter(Mode mode, const std::string& causeStart, int at_ms = 30, double ran_s = 0.0) {
  Bench b(probe(mode, at_ms));
  b.run(10);
  ASSERT_TRUE(b.host.dead()) << causeStart;
  EXPECT_EQ(b.host.faultCause().rfind(causeStart, 0), 0u) << b.host.faultCause();
  EXPECT_EQ(b.log.of("firmware_fault").size(), 1u);
  EXPECT_TRUE(b.out.relayClose);  // closed at init, frozen
  EXPECT_NEAR(b.host.faultTime_s(), at_ms * 1e-3 + ran_s, 1e-6) << b.host.faultCause();
  const uint64_t runs = b.host.taskRuns(0);
  b.run(5);
  EXPECT_EQ(b.host.taskRuns(0), runs);
  EXPECT_NE(b.host.status().find("firmware_fault at"), std::string::npos);
}

TEST(FirmwareHost, ACrashStopsTheFirmwareNotTheSimulator) {
  expectDeadAfter(CRASH, "crash in task 0 (period 10 ms): SIGSEGV");
  expectDeadAfter(DIV0, "crash in task 0 (period 10 ms): SIGFPE");
}

TEST(FirmwareHost, AbortInInitIsACrash) {
  Bench b(probe(ABORT));
  b.run(2);
  ASSERT_TRUE(b.host.dead());
  EXPECT_EQ(b.host.faultCause().rfind("crash in init: SIGABRT", 0), 0u) << b.host.faultCause();
}

TEST(FirmwareHost, AHangIsStoppedByTheWatchdog) { expectDeadAfter(HANG, "hang in task 0 (period 10 ms)"); }

TEST(FirmwareHost, ContractBreaksStopTheFirmware) {
  expectDeadAfter(BAD_BUS, "contract break in task 0 (period 10 ms): bus_transfer on bus 9");
  expectDeadAfter(BIG_RX, "contract break in task 0 (period 10 ms): bus_transfer of 4 bytes out, 1025 in");
  // 250 µs a transfer against the 10 ms budget (the period): the 41st transfer is over.
  expectDeadAfter(BUS_LOOP, "contract break in task 0 (period 10 ms): ran 10.250 ms of simulated time", 30, 10.25e-3);
}

// The handlers are the process's own again after a guarded call.
TEST(FirmwareHost, RestoresTheSignalHandlersAfterACrash) {
  struct sigaction before{}, after{};
  sigaction(SIGSEGV, nullptr, &before);
  expectDeadAfter(CRASH, "crash in task 0");
  sigaction(SIGSEGV, nullptr, &after);
  EXPECT_EQ(before.sa_handler, after.sa_handler);
  EXPECT_EQ(before.sa_flags & SA_SIGINFO, after.sa_flags & SA_SIGINFO);
}

TEST(FirmwareHost, ATripEventReachesTheSinkAsATrip) {
  Bench b(probe(TRIP, 20));
  b.run(5);
  ASSERT_EQ(b.log.trips.size(), 1u);
  EXPECT_EQ(b.log.trips[0].detail, "overcurrent_discharge");
  EXPECT_DOUBLE_EQ(b.log.trips[0].t, 0.020);
  EXPECT_FALSE(b.host.dead());
}

// A user's trip report in another spelling ("TRIP x", "trip:x") is not the run's trip,
// and was not a word either: the summary said "no trip" while the firmware had opened
// the relay. It is named once, as a config_warning (which packsim check prints); the
// exact "trip: " still counts, another word ("tripped") is no trip report.
TEST(FirmwareHost, AnEventThatReadsAsATripButIsNotTripColonIsNamedOnce) {
  Bench b(probe(TRIP_TEXTS, 20));
  b.run(5);
  ASSERT_EQ(b.log.trips.size(), 1u);
  EXPECT_EQ(b.log.trips[0].detail, "comm_loss");
  std::vector<std::string> warnings;  // (the probe's 15 ms task has its own config_warning)
  for (const std::string& w : b.log.of("config_warning"))
    if (w.find("reads as a trip") != std::string::npos) warnings.push_back(w);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_EQ(warnings[0].rfind("firmware event 'TRIP cell_overvoltage' at 0.020000 s reads as a trip report but is "
                              "not counted as one: a trip is an event that starts exactly with 'trip: '",
                              0),
            0u)
      << warnings[0];
  EXPECT_EQ(b.log.of("firmware").size(), 4u);  // every text still in the event log
}

}  // namespace
}  // namespace packsim
