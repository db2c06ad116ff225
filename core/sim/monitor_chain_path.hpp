// HardwareSim's monitor ICs: the register-level chain of the scenario's part (made by its
// descriptor, core/parts; models/afe, monitor_part.hpp), which every firmware talks to byte for byte over bus
// 0 (packsim's own core included). Each tick the chain's analog inputs are filled from
// a MonitorTruth (cells at the pins, injected channel errors, thermistors, die = board +
// die_rise_C, current), scripted comm faults are set on its devices, and it advances to
// t. Its FAULT line, balancing switches and (a part with its own) FETs drive the rest of the
// hardware.
#pragma once
#include <vector>

#include "core/firmware/monitor_bus.hpp"
#include "core/sim/result.hpp"
#include "models/afe/monitor_truth.hpp"

namespace packsim {

class MonitorChainPath {
 public:
  MonitorChainPath(const MonitorConfig& cfg, int cellCount, uint64_t seed);

  // A truth of the right shape for this chain, to fill each tick.
  MonitorTruth makeTruth() const;
  int thermistorChannels() const { return cfg_.devices * cfg_.thermistors_per_device; }
  void update(double t, const MonitorTruth& truth);
  bool faultLine() const { return bus_.chain->faultLine(); }
  bool balancing(int cell) const;  // series position
  // The share of [t0, t1) its switch, held on, conducts (the part's pauses for conversions).
  double balancingDuty(int cell, double t0, double t1) const;
  // Every cell's switch (on[cell], 0/1) and its share of [t0, t1) (duty[cell], 1 when
  // off): balancing(cell) and balancingDuty(cell, t0, t1) of each cell, read device by
  // device (one switch register read per device, no search per cell).
  void balancingSwitches(double t0, double t1, uint8_t* on, double* duty) const;
  // Device d's thermistor bias current (A) and the cell it draws from (its top one).
  double thermistorBias_A(int d) const;
  int topCell(int d) const { return firstCell_[static_cast<size_t>(d)] + bus_.chain->cellsOf(d) - 1; }
  int devices() const { return bus_.chain->deviceCount(); }
  // (a part without FET drivers: always, no virtual call a tick)
  bool dischargeAllowed() const { return !fetDrivers_ || part_->dischargeFetOn(); }
  bool chargeAllowed() const { return !fetDrivers_ || part_->chargeFetOn(); }
  std::string fetOffCause(bool discharge) const { return bus_.chain->fetOffCause(discharge); }
  std::string faultCause() const { return bus_.chain->faultCause(); }
  const RegisterMisuseLog& misuse() const { return part_->misuse(); }  // writes the part ignored
  // What the MCU has read of each device so far (monitor_part.hpp), device d's cell
  // count and its bottom cell's position in this chain.
  const MonitorChain::ReadCoverage& readCoverage() const { return part_->readCoverage(); }
  int cellsOf(int d) const { return bus_.chain->cellsOf(d); }
  int firstCell(int d) const { return firstCell_[static_cast<size_t>(d)]; }
  int thermistorsPerDevice() const { return cfg_.thermistors_per_device; }
  // output.bus_trace: every transaction from now on as rows of `sink`, on bus `bus`.
  void traceInto(std::vector<BusTraceRow>& sink, int bus);
  std::vector<MonitorBus*> buses() { return {&bus_}; }

 private:
  MonitorConfig cfg_;
  int cells_;
  MonitorBus bus_;
  const MonitorChain* part_;  // the part's chain (bus_.chain, or what a trace wraps)
  bool fetDrivers_ = false;   // part_->hasFetDrivers()
  std::vector<int> firstCell_;  // per device: its bottom cell's series position
  // The comm faults (per device) and broken link the chain was last given, healthy and
  // intact from the start. They change only when the scenario scripts one, and each is a
  // virtual call into the part: handed on only when they differ.
  std::vector<MonitorDeviceFault> commGiven_;
  int brokenGiven_ = -1;
  // Hands f on to device d unless the chain has it already (the test inline: the usual
  // tick's whole work, a call per device and tick otherwise).
  void giveCommFault(MonitorChain& c, int d, const MonitorDeviceFault& f) {
    if (!(commGiven_[static_cast<size_t>(d)] == f)) handOnCommFault(c, d, f);
  }
  void handOnCommFault(MonitorChain& c, int d, const MonitorDeviceFault& f);
  // The last update handed every device its injected channel errors (the truth's cells
  // reached them): a truth whose errors are unchanged since then needs none handed on.
  bool errorsGiven_ = false;
};

}  // namespace packsim
