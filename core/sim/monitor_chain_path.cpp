#include "core/sim/monitor_chain_path.hpp"

#include <algorithm>
#include <stdexcept>

#include "core/parts/monitor_parts.hpp"
#include "core/sim/bus_trace.hpp"
#include "models/afe/byte_copy.hpp"

namespace packsim {

MonitorChainPath::MonitorChainPath(const MonitorConfig& cfg, int cellCount, uint64_t seed)
    : cfg_(cfg), cells_(cellCount) {
  bus_.chain = monitorPart(cfg.model).make_chain(cfg, cellCount, seed);  // its register-level model
  part_ = bus_.chain.get();
  fetDrivers_ = part_->hasFetDrivers();
  int first = 0;
  for (int d = 0; d < bus_.chain->deviceCount(); ++d) {
    firstCell_.push_back(first);
    first += bus_.chain->cellsOf(d);
    bus_.chain->setCommFault(d, MonitorDeviceFault{});
  }
  commGiven_.assign(firstCell_.size(), MonitorDeviceFault{});
  bus_.chain->setBrokenLinkAbove(brokenGiven_);
}

MonitorTruth MonitorChainPath::makeTruth() const {
  return MonitorTruth(cells_, bus_.chain->deviceCount(), thermistorChannels());
}

void MonitorChainPath::update(double t, const MonitorTruth& truth) {
  MonitorChain& c = *bus_.chain;
  const int perDevice = cfg_.thermistors_per_device;
  const bool unloaded = truth.cell_V != nullptr && truth.cell_unloaded_V != nullptr;
  // The unloaded view is the loaded one itself (no balancing switch on: HardwareSim's
  // measurementView): a device covered whole keeps no second copy (cellsSeen reads
  // cell_V when cell_unloaded_V is empty), one pass over its cells less a tick.
  const bool sameView = unloaded && truth.cell_unloaded_V == truth.cell_V;
  // The injected channel errors as the devices hold them already (the usual tick): not
  // copied again, two passes over the cells less a tick.
  const bool errorsHeld = truth.channel_errors_unchanged && errorsGiven_;
  const size_t truthCells = truth.cell_V != nullptr ? static_cast<size_t>(cells_) : 0;  // the truth is made for cells_
  const int devices = static_cast<int>(firstCell_.size());  // c.deviceCount(), without the virtual call
  for (int d = 0; d < devices; ++d) {
    DeviceAnalog& a = c.analog(d);
    const size_t first = static_cast<size_t>(firstCell_[static_cast<size_t>(d)]);
    // Its cells in the truth (all of them in a stack as built), each array in one pass.
    const size_t n = first < truthCells ? std::min(a.cell_V.size(), truthCells - first) : 0;
    const bool ownUnloaded = unloaded && !(sameView && n == a.cell_V.size());
    a.cell_unloaded_V.resize(ownUnloaded ? a.cell_V.size() : 0);
    if (n > 0) {
      // (copyValues: a cell or two by assignment, not four library calls a tick)
      copyValues(a.cell_V.data(), truth.cell_V + first, n);
      if (ownUnloaded) copyValues(a.cell_unloaded_V.data(), truth.cell_unloaded_V + first, n);
      if (!errorsHeld) {
        copyValues(a.cell_gain_error.data(), truth.cell_gain_error.data() + first, std::min(n, a.cell_gain_error.size()));
        copyValues(a.cell_offset_V.data(), truth.cell_offset_V.data() + first, std::min(n, a.cell_offset_V.size()));
      }
    }
    // Its thermistor channels in the truth (those it has inputs for), each array in one pass.
    const size_t base = static_cast<size_t>(d) * static_cast<size_t>(std::max(perDevice, 0));
    const size_t k = base < truth.therm_C.size()
                         ? std::min({a.therm_C.size(), static_cast<size_t>(std::max(perDevice, 0)), truth.therm_C.size() - base})
                         : 0;
    if (k > 0) {
      copyValues(a.therm_C.data(), truth.therm_C.data() + base, k);
      copyValues(a.therm_fault.data(), truth.therm_fault.data() + base, std::min(k, a.therm_fault.size()));
    }
    a.die_C = (static_cast<size_t>(d) < truth.board_C.size() ? truth.board_C[static_cast<size_t>(d)] : 25.0) +
              cfg_.die_rise_C;
    a.current_A = truth.current_A;
    a.host_opens_balancing = truth.host_opens_balancing;
    giveCommFault(c, d, static_cast<size_t>(d) < truth.comm.size() ? truth.comm[static_cast<size_t>(d)] : kHealthyDevice);
  }
  errorsGiven_ = truthCells > 0;
  if (truth.broken_link_above != brokenGiven_) {
    c.setBrokenLinkAbove(truth.broken_link_above);
    brokenGiven_ = truth.broken_link_above;
  }
  bus_.advanceTo(t);
}

void MonitorChainPath::handOnCommFault(MonitorChain& c, int d, const MonitorDeviceFault& f) {
  commGiven_[static_cast<size_t>(d)] = f;
  c.setCommFault(d, f);
}

void MonitorChainPath::traceInto(std::vector<BusTraceRow>& sink, int bus) {
  bus_.chain = std::make_unique<TracedChain>(std::move(bus_.chain), bus, sink);
}

double MonitorChainPath::thermistorBias_A(int d) const {
  return cfg_.thermistors_per_device > 0 && bus_.chain->thermistorBias(d) ? cfg_.thermistor_bias_A : 0.0;
}

bool MonitorChainPath::balancing(int cell) const {
  const auto it = std::upper_bound(firstCell_.begin(), firstCell_.end(), cell);
  const int d = static_cast<int>(it - firstCell_.begin()) - 1;
  return d >= 0 && bus_.chain->balancing(d, cell - firstCell_[static_cast<size_t>(d)]);
}

void MonitorChainPath::balancingSwitches(double t0, double t1, uint8_t* on, double* duty) const {
  const MonitorChain& c = *bus_.chain;
  int cell = 0;
  const int devices = c.deviceCount();
  for (int d = 0; d < devices; ++d) {
    const uint32_t mask = c.balancingMask(d);
    const int n = c.cellsOf(d);
    if (mask == 0) {  // the usual device: every switch off, a duty of 1 each (no call per cell)
      // (its run of cells as two plain fills: the loop with both bounds in its test stored
      // one byte and one double per turn, some 10 instructions a cell; the switches by
      // zeroBytes, in place, where fill_n was a memset call)
      const int k = std::min(n, cells_ - cell);
      if (k > 0) {
        zeroBytes(on + cell, static_cast<size_t>(k));
        std::fill_n(duty + cell, k, 1.0);
        cell += k;
      }
      continue;
    }
    for (int k = 0; k < n && cell < cells_; ++k, ++cell) {
      const bool sw = (mask >> k) & 1u;
      on[cell] = sw ? 1 : 0;
      duty[cell] = sw ? c.balancingDuty(d, k, t0, t1) : 1.0;
    }
  }
  for (; cell < cells_; ++cell) {  // cells beyond the devices' inputs (none in a valid stack): as asked one by one
    on[cell] = balancing(cell) ? 1 : 0;
    duty[cell] = on[cell] ? balancingDuty(cell, t0, t1) : 1.0;
  }
}

double MonitorChainPath::balancingDuty(int cell, double t0, double t1) const {
  const auto it = std::upper_bound(firstCell_.begin(), firstCell_.end(), cell);
  const int d = static_cast<int>(it - firstCell_.begin()) - 1;
  return d >= 0 ? bus_.chain->balancingDuty(d, cell - firstCell_[static_cast<size_t>(d)], t0, t1) : 1.0;
}

}  // namespace packsim
