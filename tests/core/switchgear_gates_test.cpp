// HwSwitchgear keeps its last gates (relays stepped, FET gates and paths) while the lines,
// the weld fault and the fuse stay as they were and both relays are at rest. Against the
// step written out here (the one it replaced: both relays stepped and every gate and path
// decided at every call): the same switch states, relays and bus, bit for bit, through
// random lines with operate and release delays, the FAULT line, a weld and a fuse that
// blows, for each FET control.
#include <gtest/gtest.h>

#include <random>

#include "core/sim/hw_switchgear.hpp"
#include "models/hw/mosfet.hpp"
#include "models/hw/precharge.hpp"

namespace packsim {
namespace {

// The step as it was: what HwSwitchgear::tick gave before its gates were kept.
struct PlainSwitchgear {
  const HardwareConfig& hw;
  RelayState relay, precharge;
  FuseState fuse;
  double bus_V = 0.0;

  SwitchState tick(double t, double dt, const SwitchDrive& d, const HardwareFaults& f, const PlantSignals& sig) {
    fuseStep(hw.fuse, fuse, sig.pack_current_A, dt);
    const bool drive = !(hw.fault_line_opens_relay && d.faultLine);
    relayStep(hw.relay, relay, d.relayPin && drive, f.relay_welded, t);
    relayStep(hw.precharge_relay, precharge, d.prechargePin && drive, false, t);
    SwitchState s;
    s.dsg = fetGateOn(hw.fet_control, d.dischargePin, d.afeDischarge);
    s.chg = fetGateOn(hw.fet_control, d.chargePin, d.afeCharge);
    s.dischargeBlocked = fuse.blown || !fetPairConducts(hw.fet_paths, hw.discharge_fet, s.dsg, hw.charge_fet, s.chg, 1.0);
    s.chargeBlocked = fuse.blown || !fetPairConducts(hw.fet_paths, hw.discharge_fet, s.dsg, hw.charge_fet, s.chg, -1.0);
    s.mainClosed = relay.closed && !fuse.blown;
    if (s.mainClosed) {
      bus_V = sig.pack_voltage_V;
    } else if (precharge.closed && !s.dischargeBlocked) {
      s.precharge_A = prechargeStep(hw.precharge, sig.pack_voltage_V, bus_V, dt);
    } else {
      busIdleStep(hw.precharge, bus_V, dt);
    }
    return s;
  }
};

void expectSameAsPlainStep(FetControl control, uint32_t seed) {
  HardwareConfig hw;
  hw.fet_control = control;
  hw.relay.close_delay_s = 0.025;
  hw.relay.open_delay_s = 0.01;
  hw.precharge_relay.close_delay_s = 0.02;
  hw.fuse.rated_A = 30.0;
  hw.fuse.i2t_A2s = 50.0;
  HwSwitchgear kept(hw);
  PlainSwitchgear plain{hw};
  HardwareFaults f;
  PlantSignals sig;
  sig.pack_voltage_V = 48.0;
  std::mt19937 gen(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  SwitchDrive d;
  const double dt = 0.01;
  for (int k = 0; k < 20000; ++k) {
    // Lines that hold for a while and now and then change; a weld for a stretch; a
    // current that blows the fuse late in the run.
    if (u(gen) < 0.05) d.relayPin = u(gen) < 0.6;
    if (u(gen) < 0.05) d.prechargePin = u(gen) < 0.5;
    if (u(gen) < 0.03) d.dischargePin = u(gen) < 0.7;
    if (u(gen) < 0.03) d.chargePin = u(gen) < 0.7;
    if (u(gen) < 0.02) d.afeDischarge = u(gen) < 0.8;
    if (u(gen) < 0.02) d.afeCharge = u(gen) < 0.8;
    if (u(gen) < 0.01) d.faultLine = u(gen) < 0.3;
    f.relay_welded = k >= 5000 && k < 8000;
    sig.pack_current_A = k >= 15000 ? 200.0 : 10.0 * u(gen);
    const double t = k * dt;
    const SwitchState a = kept.tick(t, dt, d, f, sig), b = plain.tick(t, dt, d, f, sig);
    ASSERT_EQ(a.mainClosed, b.mainClosed) << k;
    ASSERT_EQ(a.dsg, b.dsg) << k;
    ASSERT_EQ(a.chg, b.chg) << k;
    ASSERT_EQ(a.dischargeBlocked, b.dischargeBlocked) << k;
    ASSERT_EQ(a.chargeBlocked, b.chargeBlocked) << k;
    ASSERT_EQ(a.precharge_A, b.precharge_A) << k;
    ASSERT_EQ(kept.relayClosed(), plain.relay.closed) << k;
    ASSERT_EQ(kept.relayCoil(), plain.relay.coil) << k;
    ASSERT_EQ(kept.bus_V(), plain.bus_V) << k;
  }
  EXPECT_TRUE(plain.fuse.blown) << "the run reached a blown fuse";
}

TEST(SwitchgearGates, KeptGatesAreThePlainStepForEveryFetControl) {
  uint32_t seed = 1;
  for (FetControl c : {FetControl::Mcu, FetControl::Afe, FetControl::AfeAndMcu}) expectSameAsPlainStep(c, seed++);
}

}  // namespace
}  // namespace packsim
