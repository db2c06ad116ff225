#include "core/sim/bms_bridge.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/sim/same_instant.hpp"

#include "models/hw/charger.hpp"
#include "models/random/random.hpp"
#include "models/hw/mosfet.hpp"
#include "models/hw/precharge.hpp"

namespace packsim {

HardwareSim::HardwareSim(const Scenario& s, const Plant& plant)
    : s_(s), plant_(plant), boards_(monitorBoards(s.hardware, s.pack.series)) {
  // One register-level stack per monitor board; board 0 draws from the run's seed (a
  // single-board pack as ever), the others from their own streams.
  for (const MonitorBoard& b : boards_) {
    MonitorConfig a = s.hardware.afe;
    a.devices = b.devices;
    const uint64_t seed = b.index == 0 ? s.run.seed : deriveSeed(s.run.seed, static_cast<uint64_t>(RngStream::MonitorBoard) + static_cast<uint64_t>(b.index));
    chains_.push_back(std::make_unique<MonitorChainPath>(a, b.cells, seed));
    truths_.push_back(chains_.back()->makeTruth());
    if (s.output.bus_trace) chains_.back()->traceInto(busTrace_, b.index);
  }
  if (s.hardware.active_balancer.present) moduleV_.assign(static_cast<size_t>(s.pack.series), 0.0);
  // The node each thermistor channel reads: its group's first cell, the FETs' node, its
  // balancing board's node.
  for (const ThermistorChannel& ch : s.hardware.thermistors.channels) {
    const int node = ch.site == ThermSite::Cell  ? ch.group * plant.pack().parallel
                     : ch.site == ThermSite::Fet ? plant.thermal().find(ch.node)
                                                      : plant.boardNodeOf(ch.board);
    thermNode_.push_back(static_cast<size_t>(node));
  }
}

int HardwareSim::boardOfGroup(int g) const {
  for (const MonitorBoard& b : boards_)
    if (g < b.firstCell + b.cells) return b.index;
  return static_cast<int>(boards_.size()) - 1;
}

bool HardwareSim::balancing(int g) const {
  const MonitorBoard& b = boards_[static_cast<size_t>(boardOfGroup(g))];
  return chains_[static_cast<size_t>(b.index)]->balancing(g - b.firstCell);
}

double HardwareSim::balancingDuty(int g, double t0, double t1) const {
  const MonitorBoard& b = boards_[static_cast<size_t>(boardOfGroup(g))];
  return chains_[static_cast<size_t>(b.index)]->balancingDuty(g - b.firstCell, t0, t1);
}

bool HardwareSim::faultLine() const {
  for (const auto& c : chains_)
    if (c->faultLine()) return true;
  return false;
}

void HardwareSim::sample(double t, const PlantSignals& sig, const PlantSignals& unloaded, const HardwareFaults& f,
                         Rng& rng, bms::Inputs& in) {
  const HardwareConfig& hw = s_.hardware;
  auto thermFault = [&](size_t k) {
    return k < f.thermistor.size() ? f.thermistor[k] : ThermistorFault::None;
  };
  auto thermTemp = [&](size_t k) { return sig.node_temp_C[thermNode_[k]]; };
  // Each board's stack: its cells at the pins, each device's die on the balancing board
  // of its first cell (or the ambient air without one), its thermistor inputs, its
  // devices' comm faults; a broken link cuts off the devices above it on that board.
  for (const MonitorBoard& b : boards_) {
    MonitorTruth& tr = truths_[static_cast<size_t>(b.index)];
    tr.cell_unloaded_V.resize(tr.cell_V.size());
    tr.host_opens_balancing = s_.bms.balancing.measure_paused;
    for (int i = 0; i < b.cells; ++i) {
      const size_t gi = static_cast<size_t>(b.firstCell + i), li = static_cast<size_t>(i);
      tr.cell_V[li] = sig.group_voltage_V[gi];
      tr.cell_unloaded_V[li] = unloaded.group_voltage_V[gi];
      tr.cell_gain_error[li] = gi < f.cell_channel.size() ? f.cell_channel[gi].gain_error : 0.0;
      tr.cell_offset_V[li] = gi < f.cell_channel.size() ? f.cell_channel[gi].offset_V : 0.0;
    }
    for (size_t d = 0; d < tr.board_C.size(); ++d) {
      const int node = plant_.boardNodeOfGroup(b.firstCell + static_cast<int>(d) * hw.afe.cells_per_device);
      tr.board_C[d] = node >= 0 ? sig.node_temp_C[static_cast<size_t>(node)] : sig.ambient_C;
    }
    for (size_t j = 0; j < tr.therm_C.size(); ++j) {
      const bool used = j < b.afeChannels.size();
      tr.therm_C[j] = used ? thermTemp(static_cast<size_t>(b.afeChannels[j])) : 25.0;
      tr.therm_fault[j] = used ? thermFault(static_cast<size_t>(b.afeChannels[j])) : ThermistorFault::None;
    }
    const int cut = f.broken_link_above - b.firstDevice;  // local index of the last device still linked
    const bool cutHere = f.broken_link_above >= 0 && cut >= 0 && cut < b.devices;
    for (size_t d = 0; d < tr.comm.size(); ++d) {
      const size_t gd = static_cast<size_t>(b.firstDevice) + d;
      tr.comm[d] = gd < f.device.size() ? f.device[gd] : MonitorDeviceFault{};
      if (cutHere && static_cast<int>(d) > cut && f.broken_link_byte >= 0) tr.comm[d].stuck_byte = f.broken_link_byte;
    }
    tr.broken_link_above = cutHere && f.broken_link_byte < 0 ? cut : -1;
    tr.current_A = sig.pack_current_A;
    chains_[static_cast<size_t>(b.index)]->update(t, tr);  // the board's host reads it over its bus
  }

  // Thermistors beyond the monitor inputs sit on the pack host's own ADC.
  const std::vector<int>& mcu = boards_.front().mcuChannels;
  for (size_t j = 0; j < mcu.size(); ++j) {
    const size_t k = static_cast<size_t>(mcu[j]);
    const ThermistorFault sf = thermFault(k);
    const int64_t code = sf == ThermistorFault::Open    ? hw.thermistor.fullScaleCode()
                         : sf == ThermistorFault::Short ? 0
                                                    : hw.thermistor.code(thermTemp(k), rng);
    in.mcuThermistorCode[j] = static_cast<uint16_t>(code);
  }
  const double senseOffset_A = f.current_sensor_offset_A + f.current_sensor_drift_A_per_s * t;
  in.currentCode = static_cast<int32_t>(hw.current_sense.code(sig.pack_current_A + senseOffset_A, rng));
  in.busVoltageCode = static_cast<uint16_t>(hw.bus_adc.convert(st_.bus_V, rng));
  in.eSwitchInternal = f.estop_internal_pulled;
  in.eSwitchExternal = f.estop_external_pulled;
  in.relayAux = relay_.closed;
  in.monitorFaultPin = faultLine();
  in.chargerPresent = s_.bms.charger_present;
  in.runRequest = s_.bms.run_request && !f.key_off;
  in.resetRequest = f.reset_requested;
  in.now_ms = static_cast<uint32_t>(std::llround(t * 1e3));
}

HardwareSim::Paths HardwareSim::switchPaths(double t, const bms::Outputs& out, const HardwareFaults& f) {
  const HardwareConfig& hw = s_.hardware;
  // The monitor FAULT line sits in series with the relay drive: it opens the relay
  // whatever the MCU commands.
  const bool drive = !(hw.fault_line_opens_relay && st_.fault_line);
  relayWelded_ = f.relay_welded;
  relayStep(hw.relay, relay_, out.relayClose && drive, f.relay_welded, t);
  relayStep(hw.precharge_relay, precharge_, out.prechargeClose && drive, false, t);
  Paths p;
  p.dsg = out.dischargeFetOn && chains_.front()->dischargeAllowed();  // a part with FETs: one board
  p.chg = out.chargeFetOn && chains_.front()->chargeAllowed();
  p.dischargeBlocked = fuse_.blown || !fetPairConducts(hw.fet_paths, hw.discharge_fet, p.dsg, hw.charge_fet, p.chg, 1.0);
  p.chargeBlocked = fuse_.blown || !fetPairConducts(hw.fet_paths, hw.discharge_fet, p.dsg, hw.charge_fet, p.chg, -1.0);
  p.mainClosed = relay_.closed && !fuse_.blown;
  return p;
}

bool HardwareSim::actuate(double t, const bms::Outputs& out, const PlantSignals& sig, const HardwareFaults& f,
                          PlantInputs& pin) {
  const HardwareConfig& hw = s_.hardware;
  const double dt = s_.bms.tick_s;
  st_.fault_line = faultLine();

  // The current of the tick that just ended heats the fuse (before the paths are
  // judged: a fuse that blew opens them now).
  fuseStep(hw.fuse, fuse_, sig.pack_current_A, dt);
  const Paths p = switchPaths(t, out, f);
  const bool dsg = p.dsg, chg = p.chg, dischargeBlocked = p.dischargeBlocked, chargeBlocked = p.chargeBlocked;
  const bool mainClosed = p.mainClosed;

  double prechargeA = 0.0;
  if (mainClosed) {
    st_.bus_V = sig.pack_voltage_V;
  } else if (precharge_.closed && !dischargeBlocked) {
    prechargeA = prechargeStep(hw.precharge, sig.pack_voltage_V, st_.bus_V, dt);
  } else {
    busIdleStep(hw.precharge, st_.bus_V, dt);
  }

  st_.relay_closed = relay_.closed;
  st_.precharge_closed = precharge_.closed;
  st_.fuse_blown = fuse_.blown;
  st_.discharge_fet_on = dsg;
  st_.charge_fet_on = chg;
  st_.precharge_A = prechargeA;
  st_.fet_loss_W = mosfetLoss_W(hw.discharge_fet, dsg, fetCurrent_A(hw.fet_paths, true, sig.pack_current_A)) +
                   mosfetLoss_W(hw.charge_fet, chg, fetCurrent_A(hw.fet_paths, false, sig.pack_current_A));

  const bool changed = pin.relay_closed != mainClosed || pin.precharge_A != prechargeA ||
                       pin.discharge_blocked != dischargeBlocked || pin.charge_blocked != chargeBlocked ||
                       (plant_.fetNode() >= 0 && (pin.discharge_fet_on != dsg || pin.charge_fet_on != chg));
  const bool balancingChanged = actuateBalancing(t, out, sig, f, pin);
  const bool biasChanged = thermistorBias(pin);
  pin.relay_closed = mainClosed;
  pin.precharge_A = prechargeA;
  pin.discharge_blocked = dischargeBlocked;
  pin.charge_blocked = chargeBlocked;
  pin.discharge_fet_on = dsg;
  pin.charge_fet_on = chg;
  return changed || balancingChanged || biasChanged;
}

bool HardwareSim::actuatePins(double t, double tEnd, const bms::Outputs& out, const PlantSignals& sig,
                              const HardwareFaults& f, PlantInputs& pin) {
  const HardwareConfig& hw = s_.hardware;
  const bool prechargeWas = !pin.relay_closed && precharge_.closed && !pin.discharge_blocked;  // the RC already runs
  const Paths p = switchPaths(t, out, f);
  double prechargeA = pin.precharge_A;
  if (p.mainClosed) {
    st_.bus_V = sig.pack_voltage_V;
    prechargeA = 0.0;
  } else if (precharge_.closed && !p.dischargeBlocked) {
    if (!prechargeWas && tEnd > t) prechargeA = prechargeStep(hw.precharge, sig.pack_voltage_V, st_.bus_V, tEnd - t);
  } else {
    prechargeA = 0.0;
  }
  st_.relay_closed = relay_.closed;
  st_.precharge_closed = precharge_.closed;
  st_.discharge_fet_on = p.dsg;
  st_.charge_fet_on = p.chg;
  st_.precharge_A = prechargeA;
  st_.fet_loss_W = mosfetLoss_W(hw.discharge_fet, p.dsg, fetCurrent_A(hw.fet_paths, true, sig.pack_current_A)) +
                   mosfetLoss_W(hw.charge_fet, p.chg, fetCurrent_A(hw.fet_paths, false, sig.pack_current_A));
  bool changed = pin.relay_closed != p.mainClosed || pin.precharge_A != prechargeA ||
                 pin.discharge_blocked != p.dischargeBlocked || pin.charge_blocked != p.chargeBlocked ||
                 (plant_.fetNode() >= 0 && (pin.discharge_fet_on != p.dsg || pin.charge_fet_on != p.chg));
  pin.relay_closed = p.mainClosed;
  pin.precharge_A = prechargeA;
  pin.discharge_blocked = p.dischargeBlocked;
  pin.charge_blocked = p.chargeBlocked;
  pin.discharge_fet_on = p.dsg;
  pin.charge_fet_on = p.chg;
  // The charger stops at once when its enable drops; it starts (and follows a new
  // current request) at its controller's next step, the tick's.
  if (s_.charger.present && !out.chargerEnable && pin.charger_limit_A != 0.0) {
    pin.charger_limit_A = 0.0;
    changed = true;
  }
  return changed;
}

double HardwareSim::nextSwitch_s(double t) const {
  const HardwareConfig& hw = s_.hardware;
  double next = std::numeric_limits<double>::infinity();
  const auto pending = [&](const RelayConfig& c, const RelayState& r, bool welded) {
    double at = std::numeric_limits<double>::infinity();
    if (r.coil && !r.closed) at = r.coilChanged_s + c.close_delay_s;
    if (!r.coil && r.closed && !welded) at = r.coilChanged_s + c.open_delay_s;
    if (at > t + sameInstantTol_s(at)) next = std::min(next, at);
  };
  pending(hw.relay, relay_, relayWelded_);
  pending(hw.precharge_relay, precharge_, false);
  return next;
}

// The monitor ICs' thermistor bias, from each device's top cell while it is switched on.
bool HardwareSim::thermistorBias(PlantInputs& pin) const {
  if (!(s_.hardware.afe.thermistor_bias_A > 0.0)) return false;
  bool changed = pin.bias_A.size() != static_cast<size_t>(s_.pack.series);
  if (changed) pin.bias_A.assign(static_cast<size_t>(s_.pack.series), 0.0);
  for (const MonitorBoard& b : boards_) {
    const MonitorChainPath& c = *chains_[static_cast<size_t>(b.index)];
    for (int d = 0; d < c.devices(); ++d) {
      const size_t g = static_cast<size_t>(b.firstCell + c.topCell(d));
      const double i = c.thermistorBias_A(d);
      changed = changed || pin.bias_A[g] != i;
      pin.bias_A[g] = i;
    }
  }
  return changed;
}

const PlantSignals& HardwareSim::measurementView(double t, const double* x, const PlantInputs& pin,
                                                 const PlantSignals& sig) {
  if (std::none_of(pin.balancing.begin(), pin.balancing.end(), [](uint8_t b) { return b != 0; })) return sig;
  if (pausedSig_.cell_current_A.empty()) pausedSig_ = plant_.makeSignals();
  pausedInputs_ = pin;
  std::fill(pausedInputs_.balancing.begin(), pausedInputs_.balancing.end(), 0);
  plant_.evaluate(t, x, pausedInputs_, pausedSig_);
  return pausedSig_;
}

// Balancing switches as the monitor ICs hold them (mask and timer), the charger's
// CC-CV state under the BMS enable, and the active balancer's controller.
bool HardwareSim::actuateBalancing(double t, const bms::Outputs& out, const PlantSignals& sig,
                                   const HardwareFaults& f, PlantInputs& pin) {
  bool changed = false;
  const int series = s_.pack.series;
  if (s_.hardware.balancing.present) {
    if (pin.balancing.size() != static_cast<size_t>(series)) pin.balancing.assign(static_cast<size_t>(series), 0);
    if (pin.balance_duty.size() != static_cast<size_t>(series)) pin.balance_duty.assign(static_cast<size_t>(series), 1.0);
    for (int g = 0; g < series; ++g) {
      const uint8_t on = balancing(g) ? 1 : 0;
      // The share of the coming tick the switch conducts: the monitor IC (or the host)
      // holds it open for conversions (models/afe, balancingDuty).
      const double duty = on ? balancingDuty(g, t, t + s_.bms.tick_s) : 1.0;
      changed = changed || pin.balancing[static_cast<size_t>(g)] != on || pin.balance_duty[static_cast<size_t>(g)] != duty;
      pin.balancing[static_cast<size_t>(g)] = on;
      pin.balance_duty[static_cast<size_t>(g)] = duty;
    }
  }
  if (s_.charger.present) {
    const double setpoint = s_.charger.voltage_V + f.charger_overvoltage_V;
    const double limit = chargerStep(s_.charger, charger_, out.chargerEnable, out.chargerCurrentRequest_mA * 1e-3,
                                     sig.charger_A, sig.pack_voltage_V, setpoint);
    changed = changed || limit != pin.charger_limit_A || setpoint != pin.charger_setpoint_V;
    pin.charger_limit_A = limit;
    pin.charger_setpoint_V = setpoint;
    st_.charger_cv = charger_.cv;
    st_.charger_done = charger_.done;
  }
  const ActiveBalancerConfig& a = s_.hardware.active_balancer;
  if (a.present) {
    // Module voltages as the BMS reports them over CAN; the bus voltage is its own reading.
    for (int g = 0; g < series; ++g) moduleV_[static_cast<size_t>(g)] = out.telemetry.cellVoltage_mV[g] * 1e-3;
    const ActiveBalancerCommand cmd = activeBalancerDecide(a, moduleV_, sig.bus_V, out.state == bms::State::Error);
    if (pin.converter_A.size() != static_cast<size_t>(series)) pin.converter_A.assign(static_cast<size_t>(series), 0.0);
    for (int g = 0; g < series; ++g) {
      const double i = g == cmd.source ? a.converter_current_A : g == cmd.sink ? -a.converter_current_A : 0.0;
      changed = changed || pin.converter_A[static_cast<size_t>(g)] != i;
      pin.converter_A[static_cast<size_t>(g)] = i;
    }
    changed = changed || pin.bus_precharge != cmd.precharge;
    pin.bus_precharge = cmd.precharge;
    st_.active_safe_state = cmd.safe_state;
    st_.active_isolated = cmd.isolated;
  }
  return changed;
}

}  // namespace packsim
