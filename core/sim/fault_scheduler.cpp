#include "core/sim/fault_scheduler.hpp"

#include <algorithm>
#include <limits>
#include <cstdio>

#include "core/sim/run_tracker.hpp"
#include "core/sim/same_instant.hpp"

namespace packsim {

FaultScheduler::FaultScheduler(const Scenario& s, const Plant& plant)
    : s_(s), plant_(plant), state_(s.faults.size()), pending_(s.faults.size()) {}

double FaultScheduler::quantity(Quantity q, double t, const double* x, const PlantSignals& sig) const {
  const int cells = plant_.pack().cellCount();
  auto soc = [&](int c) { return plant_.cellStates(x, c)[CellLayout::soc]; };
  switch (q) {
    case Quantity::Time_s: return t;
    case Quantity::CellMin_V: return *std::min_element(sig.cell_voltage_V.begin(), sig.cell_voltage_V.end());
    case Quantity::CellMax_V: return *std::max_element(sig.cell_voltage_V.begin(), sig.cell_voltage_V.end());
    case Quantity::SocMin: {
      double v = soc(0);
      for (int c = 1; c < cells; ++c) v = std::min(v, soc(c));
      return v;
    }
    case Quantity::SocMax: {
      double v = soc(0);
      for (int c = 1; c < cells; ++c) v = std::max(v, soc(c));
      return v;
    }
    case Quantity::SocMean: {
      double v = 0.0;
      for (int c = 0; c < cells; ++c) v += soc(c);
      return v / cells;
    }
    case Quantity::PackCurrent_A: return sig.pack_current_A;
    case Quantity::PackVoltage_V: return sig.pack_voltage_V;
    case Quantity::TempMax_C: return *std::max_element(sig.node_temp_C.begin(), sig.node_temp_C.begin() + cells);
  }
  return 0.0;
}

// How long an injection stays on once started (0: for the rest of the run). A reset
// request without `duration_s` is a press of the button: asserted for one BMS tick.
double FaultScheduler::activeFor_s(const FaultInjection& inj) const {
  if (inj.duration_s > 0.0) return inj.duration_s;
  return inj.kind == FaultKind::ResetRequest ? s_.bms.tick_s : 0.0;
}

double FaultScheduler::nextPendingChange_s(double t) const {
  double next = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < s_.faults.size(); ++i) {
    const FaultInjection& inj = s_.faults[i];
    const Track& tr = state_[i];
    if (tr.done) continue;
    double at_s = 0.0;
    if (!tr.active) {
      if (inj.hasCondition) continue;
      at_s = inj.at_s;
    } else {
      const double d_s = activeFor_s(inj);
      if (!(d_s > 0.0)) continue;
      at_s = tr.start_s + d_s;
    }
    if (!reached(t, at_s)) next = std::min(next, at_s);
  }
  return next;
}

bool FaultScheduler::updatePending(double t, const double* x, const PlantSignals& sig, HardwareFaults& faults,
                            RunTracker& tracker) {
  bool changed = false;
  for (size_t i = 0; i < s_.faults.size(); ++i) {
    const FaultInjection& inj = s_.faults[i];
    Track& tr = state_[i];
    if (tr.done) continue;
    if (!tr.active) {
      const bool due = inj.hasCondition ? inj.when.holds(quantity(inj.when.quantity, t, x, sig)) : reached(t, inj.at_s);
      if (!due) continue;
      tr.active = true;
      tr.start_s = t;
      changed = true;
      tracker.event(t, "fault_injected", inj.injectedDetail());
    } else if (const double d_s = activeFor_s(inj); d_s > 0.0 && reached(t, tr.start_s + d_s)) {
      tr.active = false;
      tr.done = true;
      tr.end_s = t;
      --pending_;
      changed = true;
      tracker.event(t, "fault_removed", inj.describe());
    }
  }
  if (!changed) return false;
  watching_ = anyWaitingToAct();
  const HardwareFaults before = faults;
  apply(faults);
  return faults.extra_load_A != before.extra_load_A || faults.cell_heat_W != before.cell_heat_W ||
         faults.cell_leak_ohm != before.cell_leak_ohm || faults.relay_welded != before.relay_welded;
}

void FaultScheduler::reportUnreached(double t_end_s, const std::string& run_end, RunTracker& tracker) const {
  for (size_t i = 0; i < s_.faults.size(); ++i) {
    if (state_[i].start_s >= 0.0) continue;
    const FaultInjection& inj = s_.faults[i];
    char when[160];
    if (inj.hasCondition)
      std::snprintf(when, sizeof when, "when %s never held", inj.when.text.c_str());
    else
      std::snprintf(when, sizeof when, "due at %.3f s", inj.at_s);
    char end[64];
    std::snprintf(end, sizeof end, "%.3f s", t_end_s);
    tracker.event(t_end_s, "fault_not_reached",
                  inj.describe() + " (" + inj.where() + ", " + when + "; the run ended at " + end + ": " +
                      run_end + ")");
  }
}

bool FaultScheduler::waitingToAct(size_t i) const {
  return state_[i].active && needsCurrentPath(s_.faults[i]) && !state_[i].seen.acted;
}

bool FaultScheduler::anyWaitingToAct() const {
  for (size_t i = 0; i < s_.faults.size(); ++i)
    if (waitingToAct(i)) return true;
  return false;
}

void FaultScheduler::noteEffects(const PathState& p) {
  for (size_t i = 0; i < s_.faults.size(); ++i)
    if (waitingToAct(i)) noteEffect(s_.faults[i], p, state_[i].seen);
  watching_ = anyWaitingToAct();
}

void FaultScheduler::reportNoEffect(double t_end_s, RunTracker& tracker) const {
  for (size_t i = 0; i < s_.faults.size(); ++i) {
    const Track& tr = state_[i];
    const FaultInjection& inj = s_.faults[i];
    // Injected at the run's last instant: no time to act, nothing to say.
    if (tr.start_s < 0.0 || !needsCurrentPath(inj) || tr.seen.acted || !(tr.start_s < t_end_s)) continue;
    char span[96];
    if (tr.end_s >= 0.0)
      std::snprintf(span, sizeof span, "active %.3f-%.3f s", tr.start_s, tr.end_s);
    else
      std::snprintf(span, sizeof span, "active from %.3f s to the end", tr.start_s);
    tracker.event(t_end_s, "fault_no_effect",
                  inj.describe() + " (" + inj.where() + ", " + span + "): " + noEffectText(inj, tr.seen));
  }
}

// Rebuilds the fault state from every active injection (so overlapping ones add up).
void FaultScheduler::apply(HardwareFaults& f) const {
  const size_t cells = static_cast<size_t>(plant_.pack().cellCount());
  f = HardwareFaults{};
  f.cell_channel.assign(static_cast<size_t>(plant_.pack().series), ChannelError{});
  f.thermistor.assign(static_cast<size_t>(s_.hardware.thermistors.count()), ThermistorFault::None);
  f.device.assign(64, MonitorDeviceFault{});
  f.cell_heat_W.assign(cells, 0.0);
  f.cell_leak_ohm.assign(cells, 0.0);
  for (size_t i = 0; i < s_.faults.size(); ++i) {
    if (!state_[i].active) continue;
    const FaultInjection& inj = s_.faults[i];
    const size_t k = static_cast<size_t>(inj.index);
    switch (inj.kind) {
      case FaultKind::Overcurrent: f.extra_load_A += inj.value; break;
      case FaultKind::HotCell: f.cell_heat_W[k] += inj.value; break;
      case FaultKind::InternalShort: f.cell_leak_ohm[k] = inj.value; break;
      case FaultKind::EStop: (inj.external ? f.estop_external_pulled : f.estop_internal_pulled) = true; break;
      case FaultKind::DeviceSilent: f.device[k].silent = true; break;
      case FaultKind::CrcErrors: f.device[k].crc_error_rate = inj.value; break;
      case FaultKind::DeviceStuck: f.device[k].stuck_byte = static_cast<int>(inj.value); break;
      case FaultKind::BrokenLink:
        f.broken_link_above = inj.index;
        f.broken_link_byte = static_cast<int>(inj.value);
        break;
      case FaultKind::ChannelGain: f.cell_channel[k].gain_error += inj.value; break;
      case FaultKind::ChannelOffset: f.cell_channel[k].offset_V += inj.value; break;
      case FaultKind::ThermistorOpen: f.thermistor[k] = ThermistorFault::Open; break;
      case FaultKind::ThermistorShort: f.thermistor[k] = ThermistorFault::Short; break;
      case FaultKind::WeldedRelay: f.relay_welded = true; break;
      case FaultKind::CurrentSensorDrift:  // offset + rate·(t - start) = (offset - rate·start) + rate·t
        f.current_sensor_offset_A += inj.value - inj.rate_per_s * state_[i].start_s;
        f.current_sensor_drift_A_per_s += inj.rate_per_s;
        break;
      case FaultKind::ChargerOvervoltage: f.charger_overvoltage_V += inj.value; break;
      case FaultKind::HostDead:
        if (inj.index == 0)
          f.host_dead = true;
        else
          f.dead_boards |= 1u << inj.index;
        break;
      case FaultKind::ResetRequest: f.reset_requested = true; break;
      case FaultKind::KeyOff: f.key_off = true; break;
      case FaultKind::SupplyBrownout:  // overlapping dips: the deepest
        f.supply_V = f.supply_V < 0.0 ? inj.value : std::min(f.supply_V, inj.value);
        break;
    }
  }
}

}  // namespace packsim
