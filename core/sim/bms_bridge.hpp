// The simulator side of the BMS boundary: the firmware image (makeBmsConfig, coreImage:
// core/sim/bms_image.hpp) and the hardware around the MCU.
//
// HardwareSim: everything between the plant and the MCU pins, as discrete models
// advanced once per tick:
//   sample(t)   truth -> the register-level monitor chain's analog inputs (the
//               firmware reads it over the bus, monitor_chain_path.hpp); MCU
//               thermistor and current-sense codes, load-bus voltage code, GPIO
//               (E-switches, relay aux contact, monitor FAULT line, charger present,
//               run and reset requests)
//   actuate(t)  the firmware's pins at t -> relay coils (the monitor FAULT line is wired
//               in series with the coil drive, so it opens the relay without the MCU),
//               relay delays and weld, FETs (a monitor part with FETs: its own control),
//               fuse I²t, precharge RC, balancing switches (as the monitor ICs hold
//               them), charger CC-CV, active balancer controller; fills the plant's
//               inputs for [t, t + tick).
// Noise, quantisation and hardware faults live here and in models/, never in bms/.
#pragma once
#include <bms/bms_config.hpp>
#include <bms/bms_hal.hpp>

#include "core/scenario/monitor_boards.hpp"
#include "core/scenario/scenario.hpp"
#include "core/sim/bms_image.hpp"
#include "core/sim/hardware_faults.hpp"
#include "core/sim/monitor_chain_path.hpp"
#include "core/sim/plant.hpp"
#include "models/hw/fuse.hpp"
#include "models/hw/relay.hpp"
#include "models/sensors/adc.hpp"

namespace packsim {

// What the switching hardware is actually doing (for records and events).
struct HardwareStatus {
  bool relay_closed = false;      // main contact
  bool precharge_closed = false;  // precharge contact
  bool fuse_blown = false;
  bool discharge_fet_on = false;  // gate actually on (after the monitor part's own control)
  bool charge_fet_on = false;
  bool fault_line = false;        // monitor FAULT / ALERT line asserted
  double bus_V = 0.0;
  double precharge_A = 0.0;
  double fet_loss_W = 0.0;
  bool charger_cv = false;        // charger in its constant-voltage phase
  bool charger_done = false;      // charger ended on its taper current
  bool active_safe_state = false; // active balancer: a module out of range, converters off
  bool active_isolated = false;   // ... because the BMS isolated the pack
};

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
  double nextSwitch_s(double t) const;

  const HardwareStatus& status() const { return st_; }
  // The monitor boards (one unless hardware.afe.devices_per_board), board b's host's
  // buses (its register-level monitor chain) and the thermistors on the pack host's ADC.
  const std::vector<MonitorBoard>& boards() const { return boards_; }
  std::vector<MonitorBus*> monitorBuses(int board = 0) { return chains_[static_cast<size_t>(board)]->buses(); }
  int mcuThermistorCount() const { return static_cast<int>(boards_.front().mcuChannels.size()); }
  int monitorDevices() const { return s_.hardware.afe.devices; }
  // Series group g's balancing switch as its board's monitor ICs hold it.
  bool balancing(int g) const;
  // The share of [t0, t1) that switch, held on, conducts.
  double balancingDuty(int g, double t0, double t1) const;
  // The writes board b's monitor ICs ignored so far (models/afe/register_misuse.hpp).
  const RegisterMisuseLog& registerMisuse(int board) const { return chains_[static_cast<size_t>(board)]->misuse(); }
  // output.bus_trace: every monitor-bus transaction so far (core/sim/bus_trace.hpp).
  std::vector<BusTraceRow> takeBusTrace() { return std::move(busTrace_); }
  // Any board's FAULT line (the lines are wired together).
  bool faultLine() const;
  // The plant at t with every balancing switch open: what a conversion sees of a cell
  // whose switch is held open for it (the part's own pause, or the host's with
  // bms.balancing.measure_paused), without its I_bal·R0 drop (the state does not change
  // in those milliseconds); `sig` itself while no switch is on.
  const PlantSignals& measurementView(double t, const double* x, const PlantInputs& pin, const PlantSignals& sig);
  // The run may end: the charger finished and the scenario asks to stop then.
  bool chargeComplete() const { return s_.charger.present && s_.charger.stop_run_when_done && charger_.done; }

 private:
  bool actuateBalancing(double t, const bms::Outputs& out, const PlantSignals& sig, const HardwareFaults& f,
                        PlantInputs& pin);
  // The relays at t under the coil commands, the FET gates, and what conducts.
  struct Paths {
    bool dsg, chg, dischargeBlocked, chargeBlocked, mainClosed;
  };
  Paths switchPaths(double t, const bms::Outputs& out, const HardwareFaults& f);
  bool relayWelded_ = false;  // the weld fault as the last actuation saw it

  const Scenario& s_;
  const Plant& plant_;
  ChargerState charger_;
  PlantInputs pausedInputs_;      // the held inputs with every balancing switch open
  PlantSignals pausedSig_;
  std::vector<double> moduleV_;  // active balancer: module voltages received from the BMS
  int boardOfGroup(int g) const;
  bool thermistorBias(PlantInputs& pin) const;

  std::vector<MonitorBoard> boards_;
  std::vector<std::unique_ptr<MonitorChainPath>> chains_;  // per board
  std::vector<MonitorTruth> truths_;                       // per board, filled each tick
  std::vector<size_t> thermNode_;  // per thermistor channel: the thermal node it reads
  RelayState relay_, precharge_;
  FuseState fuse_;
  HardwareStatus st_;
  std::vector<BusTraceRow> busTrace_;  // the chains' TracedChain write here (output.bus_trace)
};

}  // namespace packsim
