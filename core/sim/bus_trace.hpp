// output.bus_trace: every transaction on a monitor bus, recorded as the MCU sees it. A
// TracedChain sits between the bus and the part's chain and forwards every call
// unchanged (the part answers exactly as without it); each transfer adds two rows --
// the bytes out at its start, the bytes in at its end -- with the part's decoding of
// the command (MonitorChain::describe). Off by default: without it nothing is wrapped.
#pragma once
#include <memory>
#include <vector>

#include "core/sim/result.hpp"
#include "models/afe/monitor_part.hpp"

namespace packsim {

class TracedChain final : public MonitorChain {
 public:
  TracedChain(std::unique_ptr<MonitorChain> part, int bus, std::vector<BusTraceRow>& sink)
      : part_(std::move(part)), bus_(bus), sink_(sink) {}

  int deviceCount() const override { return part_->deviceCount(); }
  int cellsOf(int d) const override { return part_->cellsOf(d); }
  DeviceAnalog& analog(int d) override { return part_->analog(d); }
  void setCommFault(int d, const MonitorDeviceFault& f) override { part_->setCommFault(d, f); }
  void setBrokenLinkAbove(int d) override { part_->setBrokenLinkAbove(d); }
  void advance(double t) override { part_->advance(t); }
  BusTransfer transfer(double t, const uint8_t* tx, size_t txLen, uint8_t* rx, size_t rxLen) override;
  bool faultLine() const override { return part_->faultLine(); }
  std::string faultCause() const override { return part_->faultCause(); }
  bool balancing(int d, int cell) const override { return part_->balancing(d, cell); }
  double balancingDuty(int d, int cell, double t0, double t1) const override {
    return part_->balancingDuty(d, cell, t0, t1);
  }
  bool dischargeFetOn() const override { return part_->dischargeFetOn(); }
  bool chargeFetOn() const override { return part_->chargeFetOn(); }
  bool thermistorBias(int d) const override { return part_->thermistorBias(d); }
  std::string describe(const uint8_t* tx, size_t txLen, size_t rxLen) const override {
    return part_->describe(tx, txLen, rxLen);
  }
  const MonitorChain& part() const { return *part_; }

 private:
  std::unique_ptr<MonitorChain> part_;
  int bus_;
  std::vector<BusTraceRow>& sink_;
};

}  // namespace packsim
