// What a fatal fault does, per protection (bms_faults.hpp FaultAction), driven tick by
// tick through the core: Isolate opens and latches at once; Monitor reports the fault
// active and never opens or latches; MonitorWhileDriving warns while the pack drives
// (state Normal) and isolates once driving ends with the fault still present, or at once
// when it arises off track (charging).
#include <bms/bms_core.hpp>
#include <gtest/gtest.h>

#include "fake_stack.hpp"

namespace {

constexpr bms::FaultId kUv = bms::FaultId::CellUnderVoltage;

struct Drive {
  bms::Config cfg = bms_test::config(12, 4);
  bms_test::FakeStack st{12, 4};
  bms_test::Rig rig;
  uint32_t t = 0;
  explicit Drive(bms::FaultAction a) {
    cfg.rules[static_cast<int>(kUv)].action = a;
    t = bms_test::run(cfg, rig.s, rig.in, rig.out, st, 0, 2000);  // closes and drives
  }
  // Runs for ms; true if the relay was commanded open at any tick.
  bool run(uint32_t ms) {
    bool opened = false;
    t = bms_test::run(cfg, rig.s, rig.in, rig.out, st, t, t + ms, [&](uint32_t) { opened = opened || !rig.out.relayClose; });
    return opened;
  }
  bool active() const { return (rig.out.faultActive & bms::faultBit(kUv)) != 0; }
  bool latched() const { return (rig.out.faultLatched & bms::faultBit(kUv)) != 0; }
};

TEST(FaultAction, IsolateOpensAndLatches) {
  Drive d(bms::FaultAction::Isolate);
  ASSERT_EQ(d.rig.out.state, bms::State::Normal);
  d.st.cell_mV[4] = 2800;
  EXPECT_TRUE(d.run(2000));
  EXPECT_TRUE(d.latched());
  EXPECT_EQ(d.rig.out.state, bms::State::Error);
}

TEST(FaultAction, MonitorWarnsAndNeverOpens) {
  Drive d(bms::FaultAction::Monitor);
  d.st.cell_mV[4] = 2800;
  EXPECT_FALSE(d.run(3000)) << "a monitored fault opened the relay while driving";
  EXPECT_TRUE(d.active());
  EXPECT_FALSE(d.latched());
  d.rig.in.runRequest = false;  // off track: still only a warning
  d.run(2000);
  EXPECT_TRUE(d.active());
  EXPECT_FALSE(d.latched());
  EXPECT_NE(d.rig.out.state, bms::State::Error);
  d.st.cell_mV[4] = 3700;  // gone: no trace left
  d.run(1000);
  EXPECT_FALSE(d.active());
}

TEST(FaultAction, MonitorWhileDrivingIsolatesOffTrack) {
  Drive d(bms::FaultAction::MonitorWhileDriving);
  d.st.cell_mV[4] = 2800;
  EXPECT_FALSE(d.run(3000)) << "opened on track";
  EXPECT_TRUE(d.active());
  EXPECT_FALSE(d.latched());
  EXPECT_EQ(d.rig.out.state, bms::State::Normal);
  // The rider keys off with the cell still low: off track the same fault isolates.
  d.rig.in.runRequest = false;
  d.run(100);
  EXPECT_TRUE(d.latched());
  EXPECT_EQ(d.rig.out.state, bms::State::Error);
  // A new run request does not close the relay: latched until a person resets it.
  d.rig.in.runRequest = true;
  EXPECT_TRUE(d.run(2000));
  EXPECT_EQ(d.rig.out.state, bms::State::Error);
}

TEST(FaultAction, MonitorWhileDrivingActsAtOnceWhileCharging) {
  Drive d(bms::FaultAction::MonitorWhileDriving);
  d.rig.in.runRequest = false;
  d.rig.in.chargerPresent = true;
  d.run(1000);
  ASSERT_EQ(d.rig.out.state, bms::State::Charge);
  d.st.cell_mV[4] = 2800;
  EXPECT_TRUE(d.run(2000));
  EXPECT_TRUE(d.latched());
}

}  // namespace
