#include "core/sim/hw_balancing.hpp"

#include <algorithm>

#include "core/sim/hw_status.hpp"
#include "core/sim/hw_sensors.hpp"
#include "core/sim/hw_take_over.hpp"

namespace packsim {

HwBalancing::HwBalancing(const Scenario& s) : s_(s) {
  if (s.hardware.active_balancer.present) moduleV_.assign(static_cast<size_t>(s.pack.series), 0.0);
}

bool HwBalancing::tick(double t, const HwSensors& sensors, const bms::Outputs& out, const PlantSignals& sig,
                       PlantInputs& pin) {
  bool changed = false;
  const int series = s_.pack.series;
  if (s_.hardware.balancing.present) {
    if (pin.balancing.size() != static_cast<size_t>(series)) pin.balancing.assign(static_cast<size_t>(series), 0);
    if (pin.balance_duty.size() != static_cast<size_t>(series)) pin.balance_duty.assign(static_cast<size_t>(series), 1.0);
    // Each switch as the monitor ICs hold it, and the share of the coming tick it
    // conducts: the monitor IC (or the host) holds it open for conversions (models/afe,
    // balancingDuty).
    on_.resize(static_cast<size_t>(series));
    duty_.resize(static_cast<size_t>(series));
    sensors.balancingSwitches(t, t + s_.bms.tick_s, on_.data(), duty_.data());
    // Compared and taken over (every group: no early exit; a word of switches, two
    // duties per compare, hw_take_over.hpp).
    const size_t n = static_cast<size_t>(series);
    const bool switched = takeOverBytes(pin.balancing.data(), on_.data(), n);
    const bool dutyChanged = takeOverDoubles(pin.balance_duty.data(), duty_.data(), n);
    changed = changed || switched || dutyChanged;
  }
  const ActiveBalancerConfig& a = s_.hardware.active_balancer;
  if (a.present) {
    // Module voltages as the BMS reports them over CAN; the bus voltage is its own reading.
    for (int g = 0; g < series; ++g) moduleV_[static_cast<size_t>(g)] = out.telemetry.cellVoltage_mV[g] * 1e-3;
    cmd_ = activeBalancerDecide(a, moduleV_, sig.bus_V, out.state == bms::State::Error);
    if (pin.converter_A.size() != static_cast<size_t>(series)) pin.converter_A.assign(static_cast<size_t>(series), 0.0);
    for (int g = 0; g < series; ++g) {
      const double i = g == cmd_.source ? a.converter_current_A : g == cmd_.sink ? -a.converter_current_A : 0.0;
      changed = changed || pin.converter_A[static_cast<size_t>(g)] != i;
      pin.converter_A[static_cast<size_t>(g)] = i;
    }
    changed = changed || pin.bus_precharge != cmd_.precharge;
    pin.bus_precharge = cmd_.precharge;
  }
  return changed;
}

void HwBalancing::report(HardwareStatus& st) const {
  if (!s_.hardware.active_balancer.present) return;
  st.active_safe_state = cmd_.safe_state;
  st.active_isolated = cmd_.isolated;
}

}  // namespace packsim
