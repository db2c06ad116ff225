// packsim's core reading the register-level monitor ICs through its own drivers
// (bms/bms_monitor.hpp over the firmware contract): the datasheet LSB of each part,
// injected communication faults as the driver reports them (CRC errors at their rate and
// what its retries leave, stuck 0x00/0xFF, silent devices, a broken daisy-chain link),
// the secondary protection's latch cleared through the bus, the BQ76952's coulomb
// counter, the time a read-out holds the bus, and a read-out too slow for its period.
#include <bms/afe/bq76pl536a_driver.hpp>
#include <bms/afe/bq76952_driver.hpp>
#include <bms/bms_afe_driver.hpp>
#include <bms/bms_firmware.hpp>
#include <bms/bms_monitor.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <cstddef>
#include <cstring>
#include <vector>

#include "../models/chain_test_board.hpp"
#include "core/parts/monitor_parts.hpp"
#include "core/sim/bms_bridge.hpp"
#include "core/sim/monitor_chain_path.hpp"
#include "core/sim/simulation.hpp"
#include "models/afe/bq76pl536a.hpp"
#include "test_support.hpp"

namespace packsim {
namespace {

Scenario stackScenario(const std::string& model, int series) {
  return test::scenarioFromYaml("name: afe\npack:\n  series: " + std::to_string(series) +
                                "\n  cell: {capacity_Ah: 5, ocv_V: 3.7, r0_ohm: 0.01}\n"
                                "hardware:\n  afe: {model: " + model + "}\n  cell_adc: {noise_mV_rms: 0}\n"
                                "load: {current_A: 0}\nrun: {duration_s: 1}\n");
}

// The scenario's chain, its truth and the core's drivers on a test board.
struct Rig {
  Scenario s;
  bms::Config cfg;
  MonitorChainPath path;
  MonitorTruth truth;
  std::vector<double> cells;  // the truth's cells (a view of them)
  test::ChainTestBoard board;
  bms::MonitorDrivers drv{};
  bms::AcquisitionState acq{};
  explicit Rig(const std::string& model, int series = 12)
      : s(stackScenario(model, series)),
        cfg(makeBmsConfig(s)),
        path(s.hardware.afe, series, 7),
        truth(path.makeTruth()),
        cells(static_cast<size_t>(series), 3.7),
        board(*path.buses()[0]->chain) {
    truth.cell_V = cells.data();
    bms::acquisitionReset(acq);
  }
  // The chain sees the truth at the board's clock; then the core's call.
  void update() { path.update(board.t_s, truth); }
  bool init() {
    update();
    return bms::monitorInit(cfg, drv, acq, board.board(), board.api());
  }
  void readAll() {
    update();
    bms::monitorReadAll(cfg, drv, acq, board.board(), board.api());
  }
  void wait(double dt_s) {
    board.t_s += dt_s;
    update();
  }
};

// The part registry: each simulator part has its firmware driver at the same index
// (the line order of bms/afe/monitor_parts.def), under the same name.
TEST(MonitorParts, EachPartHasItsDriverAtItsIndex) {
  const std::vector<const MonitorPart*>& parts = monitorParts();
  const std::vector<std::string> expected = {"bq76pl536a", "bq76pl455a", "bq76952", "ltc6811", "ltc6813"};
  ASSERT_EQ(parts.size(), expected.size());
  ASSERT_EQ(bms::afeDriverCount(), expected.size());
  for (size_t i = 0; i < parts.size(); ++i) {
    EXPECT_EQ(parts[i]->name, expected[i]);
    EXPECT_EQ(firmwarePartIndex(*parts[i]), i);
    EXPECT_EQ(std::string(bms::afeDriver(static_cast<uint8_t>(i))->name), expected[i]);
    EXPECT_EQ(&monitorPart(expected[i]), parts[i]);
  }
  EXPECT_EQ(bms::afeDriver(bms::afeDriverCount()), nullptr);
  EXPECT_THROW(monitorPart("ltc6812"), std::invalid_argument);
}

// The firmware image names the scenario's part, carries its settings from the scenario
// (here the BQ76952's CRC mode) and lets only a part with FETs of its own drive them.
TEST(MonitorParts, ImageCarriesTheScenarioPart) {
  for (const char* model : {"bq76pl536a", "bq76pl455a", "bq76952"}) {
    const bms::Config c = makeBmsConfig(stackScenario(model, 12));
    EXPECT_EQ(std::string(bms::afeDriver(c.afe.part)->name), model);
    EXPECT_EQ(bms::monitorHasFets(c), std::string(model) == "bq76952") << model;
  }
  const Scenario s = test::scenarioFromYaml(
      "name: afe\npack:\n  series: 12\n  cell: {capacity_Ah: 5, ocv_V: 3.7, r0_ohm: 0.01}\n"
      "hardware:\n  afe: {model: bq76952, crc: false}\nload: {current_A: 0}\nrun: {duration_s: 1}\n");
  bms::Config c = makeBmsConfig(s);
  EXPECT_FALSE(bms::afeSettingsGet<bms::Bq952DriverConfig>(c.afe.settings).crc);
  // Selecting a part writes its driver's defaults (the BQ76952 ships with its CRC on).
  ASSERT_TRUE(bms::afeSelect(c, c.afe.part));
  EXPECT_TRUE(bms::afeSettingsGet<bms::Bq952DriverConfig>(c.afe.settings).crc);
  EXPECT_FALSE(bms::afeSelect(c, bms::afeDriverCount()));
}

// A key of another part names the parts that have it.
TEST(MonitorParts, AnotherPartsKeyNamesItsParts) {
  auto errorOf = [](const std::string& afe) {
    return test::yamlErrorOf("name: afe\npack:\n  series: 12\n  cell: {capacity_Ah: 5, ocv_V: 3.7, r0_ohm: 0.01}\n"
                             "hardware:\n  afe: " + afe + "\nload: {current_A: 0}\nrun: {duration_s: 1}\n");
  };
  const std::string crc = errorOf("{model: bq76pl536a, crc: false}");
  EXPECT_NE(crc.find("hardware.afe.crc"), std::string::npos) << crc;
  EXPECT_NE(crc.find("only a bq76952 has `crc` (this stack is a bq76pl536a)"), std::string::npos) << crc;
  const std::string secondary = errorOf("{model: bq76952, secondary: {enabled: false}}");
  EXPECT_NE(secondary.find("only a bq76pl536a or bq76pl455a has `secondary` (this stack is a bq76952)"),
            std::string::npos) << secondary;
  const std::string boards = errorOf("{model: bq76952, cells_per_device: 12, devices_per_board: 1}");
  EXPECT_NE(boards.find("boards are for stacked parts (bq76pl536a, bq76pl455a, ltc6811 or ltc6813)"), std::string::npos) << boards;
}

// packsim's core refuses an image whose part this build has no driver for (init 5),
// before it touches the board.
TEST(MonitorParts, CoreRefusesAnImageOfAnUnknownPart) {
  Rig rig("bq76pl536a");
  std::vector<uint8_t> image = coreImage(rig.cfg);
  bms::CoreImage img{};
  std::memcpy(&img, image.data(), sizeof img);
  img.cfg.afe.part = bms::afeDriverCount();
  std::memcpy(image.data(), &img, sizeof img);
  const psfw_firmware* fw = bms::coreFirmware();
  std::vector<std::max_align_t> ram(fw->instance_bytes / sizeof(std::max_align_t) + 1);
  EXPECT_EQ(fw->init(ram.data(), rig.board.board(), rig.board.api(), image.data(), static_cast<uint32_t>(image.size())),
            5);
  EXPECT_EQ(rig.board.transfers, 0);
}

struct LsbCase {
  const char* model;
  double lsb_V;  // datasheet
};

class Lsb : public ::testing::TestWithParam<LsbCase> {};

TEST_P(Lsb, CellCodesFollowTheDatasheetLsb) {
  const LsbCase c = GetParam();
  Rig rig(c.model);
  rig.cells[0] = 3.7;
  rig.cells[1] = 2.0123;
  ASSERT_TRUE(rig.init());
  rig.wait(0.1);  // a BQ76952 converts in its own measurement loop
  rig.readAll();
  ASSERT_EQ(rig.acq.last[0], bms::FrameResult::Ok);
  for (int k = 0; k < 2; ++k) {
    const double v = rig.cells[static_cast<size_t>(k)];
    // The code is the nearest LSB step; the firmware scales it back to mV.
    const double expect_mV = std::round(v / c.lsb_V) * c.lsb_V * 1e3;
    EXPECT_NEAR(rig.acq.device[0].cell_mV[k], expect_mV, 0.5 + 1e-9) << c.model << " cell " << k;
  }
}

INSTANTIATE_TEST_SUITE_P(Monitor, Lsb,
                         ::testing::Values(LsbCase{"bq76pl536a", 6.25 / 16383.0}, LsbCase{"bq76pl455a", 5.0 / 65535.0},
                                           LsbCase{"bq76952", 1e-3}, LsbCase{"ltc6811", 100e-6},
                                           LsbCase{"ltc6813", 100e-6}),
                         [](const ::testing::TestParamInfo<LsbCase>& i) { return std::string(i.param.model); });

// Each BQ76PL536A read-out reads two blocks per device (results, flags); a reply fails its
// CRC with probability p. Without retries a read-out fails with 1 - (1 - p)²; with r
// retries each block fails only when all 1 + r attempts do: 1 - (1 - p^(1+r))².
TEST(Monitor, CrcErrorsAtTheirRateAndWhatRetriesLeave) {
  const double p = 0.3;
  for (int retries : {0, 2}) {
    Rig rig("bq76pl536a", 12);
    bms::Bq536Config settings = bms::afeSettingsGet<bms::Bq536Config>(rig.cfg.afe.settings);
    settings.crcRetries = static_cast<uint8_t>(retries);
    bms::afeSettingsPut(rig.cfg.afe.settings, settings);
    ASSERT_TRUE(rig.init());
    rig.truth.comm[1].crc_error_rate = p;
    int bad = 0, badOther = 0;
    const int n = 3000;
    for (int k = 0; k < n; ++k) {
      rig.wait(0.01);
      rig.readAll();
      bad += rig.acq.last[1] != bms::FrameResult::Ok;
      badOther += rig.acq.last[0] != bms::FrameResult::Ok;
    }
    const double q = 1.0 - std::pow(1.0 - std::pow(p, 1 + retries), 2);
    EXPECT_NEAR(bad, q * n, 5 * std::sqrt(n * q * (1 - q)) + 1) << retries << " retries";
    EXPECT_EQ(badOther, 0);
  }
}

TEST(Monitor, StuckAndSilentDevicesAndABrokenLink) {
  Rig rig("bq76pl536a", 36);  // 6 devices of 6 cells
  ASSERT_TRUE(rig.init());
  rig.truth.comm[0].stuck_byte = 0xFF;
  rig.truth.comm[1].stuck_byte = 0x00;
  rig.truth.comm[2].silent = true;
  rig.wait(0.01);
  rig.readAll();
  EXPECT_NE(rig.acq.last[0], bms::FrameResult::Ok);
  EXPECT_NE(rig.acq.last[1], bms::FrameResult::Ok);
  EXPECT_EQ(rig.acq.last[2], bms::FrameResult::Timeout);
  EXPECT_EQ(rig.acq.last[3], bms::FrameResult::Ok);
  EXPECT_EQ(rig.acq.bad[0], 1);
  // A link broken above device 4 (index 3) silences 5 and 6 but not 1-4.
  rig.truth.comm.assign(6, MonitorDeviceFault{});
  rig.truth.broken_link_above = 3;
  rig.wait(0.01);
  rig.readAll();
  for (int d = 0; d < 6; ++d)
    EXPECT_EQ(rig.acq.last[d] == bms::FrameResult::Ok, d <= 3) << "device " << d + 1;
  EXPECT_EQ(rig.acq.bad[5], 1);
  EXPECT_EQ(rig.acq.bad[0], 0) << "a good read-out resets the count";
  rig.wait(0.01);
  rig.readAll();
  EXPECT_EQ(rig.acq.bad[5], 2) << "two read-outs in a row";
}

TEST(Monitor, SecondaryOverVoltageLatchesUntilTheHostClearsIt) {
  Rig rig("bq76pl536a", 12);
  ASSERT_TRUE(rig.init());
  const SecondaryProtection& p = rig.s.hardware.afe.secondary;
  rig.cells[7] = p.cov_V + 0.05;
  for (double t = 0; t < p.cov_delay_s - 0.02; t += 0.01) rig.wait(0.01);
  EXPECT_FALSE(rig.path.faultLine()) << "before its delay";
  for (int k = 0; k < 4; ++k) rig.wait(0.01);
  EXPECT_TRUE(rig.path.faultLine());
  rig.readAll();
  EXPECT_TRUE(rig.acq.device[1].fault);
  EXPECT_FALSE(rig.acq.device[0].fault);
  rig.cells[7] = 3.7;  // condition gone: still latched
  rig.wait(1.0);
  EXPECT_TRUE(rig.path.faultLine());
  bms::monitorClearFaults(rig.cfg, rig.drv, rig.board.board(), rig.board.api());
  rig.wait(0.01);
  EXPECT_FALSE(rig.path.faultLine());
  rig.readAll();
  EXPECT_FALSE(rig.acq.device[1].fault);
  // The FAULT wire works without the link: a silent device still asserts it.
  rig.truth.comm[1].silent = true;
  rig.cells[7] = p.cov_V + 0.05;
  for (double t = 0; t < p.cov_delay_s + 0.05; t += 0.01) rig.wait(0.01);
  EXPECT_TRUE(rig.path.faultLine());
}

TEST(Monitor, Bq76952CoulombCounterIntegratesTheCurrent) {
  // 12 A for 10 s, then -4 A for 5 s: 100 A·s. The device converts every 250 ms, so the
  // counter steps in 0.25 s x I; the driver reads it (positive in discharge) in mA·s.
  Rig rig("bq76952", 16);
  ASSERT_TRUE(rig.init());
  const double t0 = rig.board.t_s;
  rig.readAll();
  const double before_As = rig.acq.device[0].charge_mAs * 1e-3;
  while (rig.board.t_s < t0 + 10.0) {
    rig.truth.current_A = 12.0;
    rig.wait(0.01);
  }
  while (rig.board.t_s < t0 + 15.0) {
    rig.truth.current_A = -4.0;
    rig.wait(0.01);
  }
  rig.truth.current_A = 0.0;
  rig.wait(0.3);  // the conversion that closes the last interval
  rig.readAll();
  ASSERT_EQ(rig.acq.last[0], bms::FrameResult::Ok);
  EXPECT_NEAR(rig.acq.device[0].charge_mAs * 1e-3 - before_As, 12.0 * 10.0 - 4.0 * 5.0, 12.0 * 0.25 + 0.1);
}

TEST(Monitor, PerChannelErrorsAreDrawnFromTheSeedWithTheirSpread) {
  // 240 channels with channel_gain_sd 1 % and channel_offset_sd 2 mV: the sample spread
  // of 240 draws lies within ±15 % of the configured one (sd of an sd estimate ≈ 4.6 %),
  // and the same seed draws the same errors.
  Scenario s = stackScenario("bq76pl536a", 240);
  s.hardware.afe.channel_gain_sd = 0.01;
  s.hardware.afe.channel_offset_sd_V = 0.002;
  const Bq76pl536aChain a(s.hardware.afe, 240, 11), b(s.hardware.afe, 240, 11), c(s.hardware.afe, 240, 12);
  double g2 = 0.0, o2 = 0.0;
  bool differs = false;
  for (int k = 0; k < 240; ++k) {
    g2 += a.channelGain(k) * a.channelGain(k);
    o2 += a.channelOffset_V(k) * a.channelOffset_V(k);
    ASSERT_EQ(a.channelGain(k), b.channelGain(k));
    differs = differs || a.channelGain(k) != c.channelGain(k);
  }
  EXPECT_NEAR(std::sqrt(g2 / 240), 0.01, 0.0015);
  EXPECT_NEAR(std::sqrt(o2 / 240), 0.002, 0.0003);
  EXPECT_TRUE(differs);
}

// The BQ76PL536A stops balancing when the timer written with the mask runs out unless
// the host writes it again: a dead host (no re-arm) cannot keep a cell draining.
TEST(Monitor, BalancingStopsWhenTheDevicesTimerRunsOutUnlessReArmed) {
  Rig rig("bq76pl536a", 12);
  ASSERT_TRUE(rig.init());
  uint32_t mask[bms::kBalanceWords] = {0b10};
  const double t0 = rig.board.t_s;
  bms::monitorWriteBalance(rig.cfg, rig.drv, rig.board.board(), rig.board.api(), mask, 10);
  rig.wait(t0 + 9.5 - rig.board.t_s);
  EXPECT_TRUE(rig.path.balancing(1));
  EXPECT_FALSE(rig.path.balancing(0));
  rig.wait(0.6);
  EXPECT_FALSE(rig.path.balancing(1)) << "10 s after the write";
  bms::monitorWriteBalance(rig.cfg, rig.drv, rig.board.board(), rig.board.api(), mask, 10);  // re-armed
  const double t1 = rig.board.t_s;
  rig.wait(t1 + 9.5 - rig.board.t_s);
  EXPECT_TRUE(rig.path.balancing(1));
  rig.wait(0.6);
  EXPECT_FALSE(rig.path.balancing(1));
}

// The hardware reads every switch each tick device by device (balancingSwitches); it
// gives what asking cell by cell does (balancing, balancingDuty), on every part, with
// switches on across devices and the host opening them around its conversions.
TEST(Monitor, SwitchesReadByDeviceAreTheSwitchesAskedCellByCell) {
  for (const char* model : {"bq76pl536a", "bq76pl455a", "bq76952", "ltc6811", "ltc6813"}) {
    Rig rig(model, 12);
    rig.truth.host_opens_balancing = true;
    ASSERT_TRUE(rig.init()) << model;
    uint32_t mask[bms::kBalanceWords] = {0b101100100110};
    bms::monitorWriteBalance(rig.cfg, rig.drv, rig.board.board(), rig.board.api(), mask, 60);
    int on = 0, paused = 0;
    for (int k = 0; k < 4; ++k) {
      rig.wait(0.01);
      const double t0 = rig.board.t_s;
      rig.readAll();
      const int cells = static_cast<int>(rig.cells.size());
      std::vector<uint8_t> sw(static_cast<size_t>(cells), 9);
      std::vector<double> duty(static_cast<size_t>(cells), -1.0);
      rig.path.balancingSwitches(t0, t0 + 0.01, sw.data(), duty.data());
      for (int c = 0; c < cells; ++c) {
        const size_t i = static_cast<size_t>(c);
        EXPECT_EQ(sw[i], rig.path.balancing(c) ? 1 : 0) << model << " cell " << c;
        const double expected = rig.path.balancing(c) ? rig.path.balancingDuty(c, t0, t0 + 0.01) : 1.0;
        EXPECT_EQ(duty[i], expected) << model << " cell " << c;
        on += sw[i];
        paused += duty[i] < 1.0;
      }
    }
    EXPECT_GT(on, 0) << model << ": no switch on";
    const std::string m(model);
    if (m == "bq76pl536a" || m == "bq76pl455a") EXPECT_GT(paused, 0) << model << ": no conversion pause";
  }
}

// A BQ76PL536A read-out on 1 Mbit/s SPI: the broadcast convert (4 bytes), the
// conversion wait (6 cells + GPAI + 2 thermistors at 6 µs), then per device the results
// (3-byte request + 19 registers + CRC) and the flags (3 + 4 + 1): 8 bits a byte.
TEST(Monitor, ReadOutHoldsTheBusForItsFramesAndConversion) {
  Rig rig("bq76pl536a", 12);
  ASSERT_TRUE(rig.init());
  rig.wait(0.01);
  const double t0 = rig.board.t_s;
  rig.readAll();
  const double expected = (4 + 2 * ((3 + 19 + 1) + (3 + 4 + 1))) * 8 / 1e6 + 9 * 6e-6;
  EXPECT_NEAR(rig.board.t_s - t0, expected, 1e-9);
}

// 60 cells = 10 devices ≈ 3 ms a read-out: fine every 10 ms tick; at a 2 ms tick it
// cannot fit. Unstated, the read-out period becomes 4 ms, the shortest whole number of
// ticks that holds it (core/sim/readout_fit.hpp); stated at 2 ms, the scenario is
// refused before t = 0 (it used to run until the firmware broke its task budget).
TEST(Monitor, AReadOutLongerThanItsPeriodGetsTheShortestPeriodThatHoldsIt) {
  std::string yaml = "name: slow\npack:\n  series: 60\n  cell: {capacity_Ah: 5, ocv_V: 3.7, r0_ohm: 0.01}\n"
                     "hardware:\n  afe: {model: bq76pl536a}\nbms: {tick_ms: TICK}\nload: {current_A: 1}\n"
                     "run: {duration_s: 1}\n";
  const auto withBms = [&](const char* bms) {
    std::string y = yaml;
    y.replace(y.find("TICK"), 4, bms);
    return test::scenarioFromYaml(y);
  };
  const RunResult fine = runScenario(withBms("10"));
  EXPECT_LT(test::eventTime(fine, "firmware_fault"), 0.0);
  EXPECT_LT(test::eventTime(fine, "config_warning", "bms.readout.period_ms"), 0.0);
  const RunResult grown = runScenario(withBms("2"));
  EXPECT_LT(test::eventTime(grown, "firmware_fault"), 0.0) << grown.summary.firmware_status;
  EXPECT_GE(test::eventTime(grown, "config_warning", "bms.readout.period_ms = 4 (default"), 0.0);
  const Scenario stated = withBms("2, readout: {period_ms: 2}");
  const std::string e = test::scenarioErrorOf([&] { runScenario(stated); });
  EXPECT_NE(e.find("the shortest period that holds it is 4 ms"), std::string::npos) << e;
}

// MonitorChainPath hands the devices no injected channel errors when the truth says they
// are unchanged since its last update, and no second copy of the cells when the unloaded
// view is the loaded one itself (no balancing switch on). Against a path given plain
// truths (errors always read, the unloaded cells in their own array): the same result
// registers, bit for bit, through errors coming, changing and going and a switch going on.
TEST(Monitor, HeldChannelErrorsAndASharedUnloadedViewConvertAsTheirCopies) {
  Rig plain("bq76pl536a", 12), quick("bq76pl536a", 12);
  std::vector<double> plainUnloaded = plain.cells, quickUnloaded = quick.cells;
  for (Rig* r : {&plain, &quick}) r->truth.host_opens_balancing = true;
  plain.truth.cell_unloaded_V = plainUnloaded.data();
  quick.truth.cell_unloaded_V = quick.cells.data();  // the same view
  ASSERT_TRUE(plain.init());
  ASSERT_TRUE(quick.init());
  const auto& a = dynamic_cast<const Bq76pl536aChain&>(*plain.path.buses()[0]->chain);
  const auto& b = dynamic_cast<const Bq76pl536aChain&>(*quick.path.buses()[0]->chain);
  for (int tick = 1; tick <= 40; ++tick) {
    // An error named on two channels from tick 10, changed at 20, gone at 30.
    const double g = tick >= 10 && tick < 30 ? (tick >= 20 ? -0.004 : 0.003) : 0.0;
    for (Rig* r : {&plain, &quick}) {
      r->truth.cell_gain_error[4] = g;
      r->truth.cell_offset_V[7] = 0.5 * g;
      for (size_t i = 0; i < r->cells.size(); ++i) r->cells[i] = 3.6 + 0.001 * static_cast<double>((tick * 7 + i * 3) % 50);
    }
    quick.truth.channel_errors_unchanged = tick != 10 && tick != 20 && tick != 30;
    // From tick 25 a switch is on: the unloaded cells are their own.
    for (size_t i = 0; i < plain.cells.size(); ++i) plainUnloaded[i] = quickUnloaded[i] = plain.cells[i] + (tick >= 25 ? 0.002 : 0.0);
    if (tick >= 25) quick.truth.cell_unloaded_V = quickUnloaded.data();
    for (Rig* r : {&plain, &quick}) {
      r->wait(0.01);
      r->readAll();
    }
    quick.truth.channel_errors_unchanged = true;  // (readAll's update: nothing changed since wait's)
    for (int d = 0; d < a.deviceCount(); ++d)
      for (uint8_t reg = BQ536_GPAI; reg < BQ536_TEMPERATURE1; ++reg)
        ASSERT_EQ(a.peek(d, reg), b.peek(d, reg)) << "tick " << tick << " device " << d << " register " << int(reg);
  }
}

}  // namespace
}  // namespace packsim
