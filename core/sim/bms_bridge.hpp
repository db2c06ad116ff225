// The simulator side of the BMS boundary: the firmware image (makeBmsConfig, coreImage:
// core/sim/bms_image.hpp) and the hardware around the MCU.
//
// HardwareSim: everything between the plant and the MCU pins, composed of small parts,
// each a state with a step (core/sim/hw_*.hpp):
//   HwSensors     the monitor boards' register-level chains, the MCU's ADCs and GPIO
//   HwSwitchgear  relays, precharge, FETs, fuse, load bus
//   HwBalancing   the balancing switches as the monitor ICs hold them; active balancer
//   HwCharger     the CC-CV charger under the BMS enable
// Per tick:
//   sample(t)   truth -> the sensors (the firmware reads the monitor chain over the bus,
//               monitor_chain_path.hpp; the MCU's own ADC codes and GPIO into bms::Inputs)
//   actuate(t)  the firmware's pins at t (bms::Outputs) -> the switchgear (the monitor FAULT
//               line is wired in series with the coil drive, so it opens the relay without
//               the MCU; a monitor part with FETs adds its own control), balancing, charger;
//               fills the plant's inputs for [t, t + tick).
// The pins reach the hardware in one place, switchDrive(out): MCU pins + the monitor part's
// FET drivers + the FAULT line -> SwitchDrive.
// Noise, quantisation and hardware faults live here and in models/, never in bms/.
#pragma once
#include <bms/bms_config.hpp>
#include <bms/bms_hal.hpp>

#include "core/scenario/monitor_boards.hpp"
#include "core/scenario/scenario.hpp"
#include "core/sim/bms_image.hpp"
#include "core/sim/hardware_faults.hpp"
#include "core/sim/hw_balancing.hpp"
#include "core/sim/hw_status.hpp"
#include "core/sim/hw_charger.hpp"
#include "core/sim/hw_fet_watch.hpp"
#include "core/sim/hw_sensors.hpp"
#include "core/sim/hw_switchgear.hpp"
#include "core/sim/plant.hpp"
#include "core/sim/read_coverage.hpp"

namespace packsim {

class HardwareSim {
 public:
  HardwareSim(const Scenario& s, const Plant& plant);

  // `unloaded`: the same instant with every balancing switch open (measurementView), what
  // a conversion sees of a cell whose switch the part or the host holds open for it.
  void sample(double t, const PlantSignals& sig, const PlantSignals& unloaded, const HardwareFaults& f, Rng& rng,
              bms::Inputs& in);
  // Returns true when an input of the plant changed (the integrator restarts).
  bool actuate(double t, const bms::Outputs& out, const PlantSignals& sig, const HardwareFaults& f, PlantInputs& pin);
  // Inside a tick, at the instant t the MCU changed a pin (or a relay's delay ran out):
  // the relay and precharge coils, the FET gates and the charger enable act from t on;
  // the precharge RC, if its path starts conducting, is solved over [t, tEnd) (the tick's
  // end). The fuse, the charger's CC-CV controller, balancing and the bus ADC stay on the
  // tick's step. Returns true when an input of the plant changed.
  bool actuatePins(double t, double tEnd, const bms::Outputs& out, const PlantSignals& sig, const HardwareFaults& f,
                   PlantInputs& pin);
  // The next instant after t at which a relay contact moves on its own (its operate or
  // release delay running out after the coil changed); +inf when none is pending.
  double nextSwitch_s(double t) const { return switchgear_.nextSwitch_s(t); }

  const HardwareStatus& status() const { return st_; }
  // The main relay's coil as last driven (off: commanded open, by the MCU or the FAULT line).
  bool relayCoil() const { return switchgear_.relayCoil(); }
  // The monitor boards (one unless hardware.afe.devices_per_board), board b's host's
  // buses (its register-level monitor chain) and the thermistors on the pack host's ADC.
  const std::vector<MonitorBoard>& boards() const { return sensors_.boards(); }
  std::vector<MonitorBus*> monitorBuses(int board = 0) { return sensors_.buses(board); }
  int mcuThermistorCount() const { return sensors_.mcuThermistorCount(); }
  int monitorDevices() const { return s_.hardware.afe.devices; }
  // Series group g's balancing switch as its board's monitor ICs hold it.
  bool balancing(int g) const { return sensors_.balancing(g); }
  // The share of [t0, t1) that switch, held on, conducts.
  double balancingDuty(int g, double t0, double t1) const { return sensors_.balancingDuty(g, t0, t1); }
  // The writes board b's monitor ICs ignored so far (models/afe/register_misuse.hpp).
  const RegisterMisuseLog& registerMisuse(int board) const { return sensors_.registerMisuse(board); }
  // output.bus_trace: every monitor-bus transaction so far (core/sim/bus_trace.hpp).
  std::vector<BusTraceRow> takeBusTrace() { return sensors_.takeBusTrace(); }
  // Any board's FAULT line (the lines are wired together).
  bool faultLine() const { return sensors_.faultLine(); }
  std::string faultLineCause() const { return sensors_.faultLineCause(); }
  // The plant at t with every balancing switch open: what a conversion sees of a cell
  // whose switch is held open for it (the part's own pause, or the host's with
  // bms.balancing.measure_paused), without its I_bal·R0 drop (the state does not change
  // in those milliseconds); `sig` itself while no switch is on.
  const PlantSignals& measurementView(double t, const double* x, const PlantInputs& pin, const PlantSignals& sig);
  // The summary's FETs lines for a run that ended at end_s: a FET that never conducted
  // although the MCU's pin or the monitor part's driver asked for it (hw_fet_watch.hpp).
  std::vector<std::string> fetNotes(double end_s) const;
  // The `monitor_unread` details of a run that ended at end_s and the count of series
  // groups the firmware never read (core/sim/read_coverage.hpp).
  UnreadReport unreadReport(double end_s) const;
  // The run may end: the charger finished and the scenario asks to stop then.
  bool chargeComplete() const { return s_.charger.present && s_.charger.stop_run_when_done && charger_.done(); }

 private:
  // The pins into the switchgear: the MCU's outputs, the monitor part's FET drivers and
  // the FAULT line as the tick began.
  SwitchDrive switchDrive(const bms::Outputs& out) const;
  void report(const SwitchState& sw, const PlantSignals& sig);
  // The FET watch, until both gates were on once: then nothing more to keep, and no call
  // (the test inline: the usual tick's whole work).
  void watchFets(double t, const SwitchDrive& d, const SwitchState& sw) {
    if (!fets_.settled()) watchUnsettledFets(t, d, sw);
  }
  void watchUnsettledFets(double t, const SwitchDrive& d, const SwitchState& sw);

  const Scenario& s_;
  const Plant& plant_;
  HwSensors sensors_;
  HwSwitchgear switchgear_;
  HwBalancing balancing_;
  HwCharger charger_;
  FetWatch fets_;
  PlantInputs pausedInputs_;      // the held inputs with every balancing switch open
  PlantSignals pausedSig_;
  HardwareStatus st_;
};

}  // namespace packsim
