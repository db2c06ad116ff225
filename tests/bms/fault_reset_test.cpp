// The firmware side of the fault matrix: for every fault the fake stack and the GPIO can
// produce, a reset request while the fault is still present does nothing (latched, relay
// open, every tick), and the same request after the condition is gone closes the relay
// again (so the test can tell the two apart). Plus the hot-cell nuisance case: a cell
// that reads over the temperature limit for less than the debounce never trips.
#include <bms/bms_core.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "fake_stack.hpp"

namespace {

struct FaultCase {
  const char* name;
  bms::FaultId id;
  std::function<void(bms_test::FakeStack&, bms::Inputs&, bool present)> set;
};

// Raw code of a thermistor at temp_C on the nominal divider (beta model, as the firmware
// converts it back).
uint16_t thermCode(const bms::Config& c, double temp_C) {
  const double r = c.scaling.thermR25_ohm * std::exp(c.scaling.thermBeta_K * (1.0 / (temp_C + 273.15) - 1.0 / 298.15));
  return static_cast<uint16_t>(std::lround(c.scaling.thermFullScaleCode * r / (r + c.scaling.thermPullup_ohm)));
}

const std::vector<FaultCase>& cases() {
  static const std::vector<FaultCase> v = {
      {"cell_overvoltage", bms::FaultId::CellOverVoltage,
       [](bms_test::FakeStack& st, bms::Inputs&, bool on) { st.cell_mV[3] = on ? 4400 : 3700; }},
      {"cell_undervoltage", bms::FaultId::CellUnderVoltage,
       [](bms_test::FakeStack& st, bms::Inputs&, bool on) { st.cell_mV[3] = on ? 2800 : 3700; }},
      {"overcurrent_discharge", bms::FaultId::OverCurrentDischarge,
       [](bms_test::FakeStack&, bms::Inputs& in, bool on) { in.currentCode = 32768 + (on ? 31000 : 0); }},
      {"overcurrent_charge", bms::FaultId::OverCurrentCharge,
       [](bms_test::FakeStack&, bms::Inputs& in, bool on) { in.currentCode = 32768 - (on ? 8000 : 0); }},
      {"estop", bms::FaultId::EStop, [](bms_test::FakeStack&, bms::Inputs& in, bool on) { in.eSwitchInternal = on; }},
      {"monitor_fault", bms::FaultId::MonitorFault,
       [](bms_test::FakeStack&, bms::Inputs& in, bool on) { in.monitorFaultPin = on; }},
      {"thermistor_fault", bms::FaultId::ThermistorFault,
       [](bms_test::FakeStack& st, bms::Inputs&, bool on) { st.thermCode[1] = on ? 4095 : 2048; }},
      {"comm_loss", bms::FaultId::CommLoss,
       [](bms_test::FakeStack& st, bms::Inputs&, bool on) { st.silent = on ? std::vector<int>{1} : std::vector<int>{}; }},
  };
  return v;
}

TEST(FaultReset, ResetWithTheFaultPresentDoesNothing) {
  for (const FaultCase& fc : cases()) {
    SCOPED_TRACE(fc.name);
    const bms::Config cfg = bms_test::config(12, 4);
    bms_test::FakeStack st(12, 4);
    bms_test::Rig rig;
    const uint32_t bit = bms::faultBit(fc.id);
    uint32_t t = bms_test::run(cfg, rig.s, rig.in, rig.out, st, 0, 2000);
    ASSERT_TRUE(rig.out.relayClose) << "the relay never closed without a fault";
    fc.set(st, rig.in, true);
    t = bms_test::run(cfg, rig.s, rig.in, rig.out, st, t, t + 3000);
    ASSERT_NE(rig.out.faultLatched & bit, 0u);
    ASSERT_EQ(rig.out.state, bms::State::Error);
    // Reset requested while the fault is still there: nothing changes, tick after tick.
    rig.in.resetRequest = true;
    t = bms_test::run(cfg, rig.s, rig.in, rig.out, st, t, t + 2000, [&](uint32_t now) {
      ASSERT_NE(rig.out.faultLatched & bit, 0u) << "unlatched at " << now;
      ASSERT_FALSE(rig.out.relayClose) << "relay closed at " << now;
      ASSERT_EQ(rig.out.state, bms::State::Error);
    });
    // The condition gone, the same request recovers.
    fc.set(st, rig.in, false);
    bool closed = false;
    t = bms_test::run(cfg, rig.s, rig.in, rig.out, st, t, t + 3000, [&](uint32_t) { closed = closed || rig.out.relayClose; });
    EXPECT_TRUE(closed) << "a reset after the fault cleared did not recover";
    EXPECT_EQ(rig.out.faultLatched & bit, 0u);
  }
}

// A hot cell that cools before the debounce ends never trips; held one tick past the
// debounce, it does.
TEST(FaultReset, HotCellCoolingBeforeTheDebounceNeverTrips) {
  const bms::Config cfg = bms_test::config(12, 4);
  const auto& ot = cfg.rules[static_cast<int>(bms::FaultId::OverTemperature)];
  const uint32_t bit = bms::faultBit(bms::FaultId::OverTemperature);
  for (const uint32_t hot_ms : {ot.delay_ms - 2 * cfg.tickPeriod_ms, ot.delay_ms + cfg.tickPeriod_ms}) {
    bms_test::FakeStack st(12, 4);
    bms_test::Rig rig;
    st.thermCode.assign(4, thermCode(cfg, 25.0));
    uint32_t t = bms_test::run(cfg, rig.s, rig.in, rig.out, st, 0, 2000);
    uint32_t seen = 0;
    st.thermCode[2] = thermCode(cfg, ot.threshold / 10.0 + 5.0);  // 5 °C over the limit
    t = bms_test::run(cfg, rig.s, rig.in, rig.out, st, t, t + hot_ms, [&](uint32_t) { seen |= rig.out.faultActive; });
    st.thermCode[2] = thermCode(cfg, ot.threshold / 10.0 - 15.0);  // cooled
    bms_test::run(cfg, rig.s, rig.in, rig.out, st, t, t + 5000, [&](uint32_t) { seen |= rig.out.faultActive; });
    if (hot_ms < ot.delay_ms) EXPECT_EQ(seen & bit, 0u) << "tripped after " << hot_ms << " ms hot";
    else EXPECT_NE(seen & bit, 0u) << "did not trip after " << hot_ms << " ms hot";
  }
}

}  // namespace
