// HardwareSim's sensors: what the MCUs read each tick.
//   - the monitor boards: one register-level monitor chain per board (its host reads it
//     over its bus, monitor_chain_path.hpp), fed with the truth: cells at the pins with
//     their channel errors, each device's die on its balancing board, its thermistor
//     inputs, its devices' comm faults and a broken link; the chains' FAULT line,
//     balancing switches, FET drivers and thermistor bias act on the rest of the hardware
//   - the pack host's own ADC: the thermistors beyond the monitor inputs, the current
//     sense, the load-bus voltage
//   - GPIO: E-switches, relay auxiliary contact, monitor FAULT line, charger present, run
//     and reset requests, and the clock
// Noise and quantisation are the models' (models/sensors, models/afe); none in bms/.
#pragma once
#include <bms/bms_hal.hpp>

#include <memory>
#include <vector>

#include "core/scenario/monitor_boards.hpp"
#include "core/scenario/scenario.hpp"
#include "core/sim/hardware_faults.hpp"
#include "core/sim/monitor_chain_path.hpp"
#include "core/sim/plant.hpp"
#include "models/afe/cell_conversion.hpp"
#include "models/sensors/adc.hpp"

namespace packsim {

class HwSensors {
 public:
  HwSensors(const Scenario& s, const Plant& plant);

  // The tick's step: the chains advance to t on the truth, and the MCU's inputs are
  // converted; `bus_V` and `relayAux` come from the switchgear.
  // `unloaded`: the same instant with every balancing switch open, what a conversion
  // sees of a cell whose switch the part or the host holds open for it.
  void sample(double t, const PlantSignals& sig, const PlantSignals& unloaded, const HardwareFaults& f, double bus_V,
              bool relayAux, Rng& rng,
              bms::Inputs& in);
  // The monitor ICs' thermistor bias, drawn from each device's top cell while it is on;
  // true when it changed. (A part without bias current, the usual one: no call.)
  bool applyBias(PlantInputs& pin) const { return s_.hardware.afe.thermistor_bias_A > 0.0 && applyBiasOn(pin); }

  const std::vector<MonitorBoard>& boards() const { return boards_; }
  std::vector<MonitorBus*> buses(int board) { return chains_[static_cast<size_t>(board)]->buses(); }
  int mcuThermistorCount() const { return static_cast<int>(boards_.front().mcuChannels.size()); }
  // Series group g's balancing switch as its board's monitor ICs hold it.
  bool balancing(int g) const;
  // The share of [t0, t1) that switch, held on, conducts.
  double balancingDuty(int g, double t0, double t1) const;
  // Every series group's switch (on[g]) and share of [t0, t1) (duty[g], 1 when off):
  // balancing(g) and balancingDuty(g, t0, t1) for all groups at once, board by board.
  void balancingSwitches(double t0, double t1, uint8_t* on, double* duty) const;
  // Any board's FAULT line (the lines are wired together).
  bool faultLine() const;
  // What holds the FAULT line, by each asserting stack's part (monitor boards named when
  // there are several): "" when released or the parts cannot say.
  std::string faultLineCause() const;
  // The monitor part's own FET drivers (a part with FETs: one board; others: always on).
  bool afeDischargeOn() const { return chains_.front()->dischargeAllowed(); }
  bool afeChargeOn() const { return chains_.front()->chargeAllowed(); }
  std::string afeFetOffCause(bool discharge) const { return chains_.front()->fetOffCause(discharge); }
  const RegisterMisuseLog& registerMisuse(int board) const { return chains_[static_cast<size_t>(board)]->misuse(); }
  const MonitorChainPath& chain(int board) const { return *chains_[static_cast<size_t>(board)]; }
  std::vector<BusTraceRow> takeBusTrace() { return std::move(busTrace_); }

 private:
  int boardOfGroup(int g) const;
  bool applyBiasOn(PlantInputs& pin) const;  // applyBias with a bias current

  const Scenario& s_;
  const Plant& plant_;
  std::vector<MonitorBoard> boards_;
  std::vector<std::unique_ptr<MonitorChainPath>> chains_;  // per board
  std::vector<MonitorTruth> truths_;                       // per board, filled each tick
  std::vector<std::vector<ChannelError>> channelsGiven_;    // per board: the channel errors its truth holds
  std::vector<size_t> thermNode_;  // per thermistor channel: the thermal node it reads
  // Per thermistor on the pack host's ADC: its conversion's kept ideal code and code range
  // (Thermistor::code without an exp while the node stays within a code, cell_conversion.hpp).
  std::vector<ThermistorCodeCache> mcuTherm_;
  AdcChannel currentAdc_;          // the current sense's converter (hardware.current_sense), built once
  std::vector<BusTraceRow> busTrace_;  // the chains' TracedChain write here (output.bus_trace)
};

}  // namespace packsim
