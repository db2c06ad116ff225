#include "core/sim/monitor_chain_path.hpp"

#include <algorithm>
#include <stdexcept>

#include "core/parts/monitor_parts.hpp"
#include "core/sim/bus_trace.hpp"

namespace packsim {

MonitorChainPath::MonitorChainPath(const MonitorConfig& cfg, int cellCount, uint64_t seed)
    : cfg_(cfg), cells_(cellCount) {
  bus_.chain = monitorPart(cfg.model).make_chain(cfg, cellCount, seed);  // its register-level model
  part_ = bus_.chain.get();
  int first = 0;
  for (int d = 0; d < bus_.chain->deviceCount(); ++d) {
    firstCell_.push_back(first);
    first += bus_.chain->cellsOf(d);
  }
}

MonitorTruth MonitorChainPath::makeTruth() const {
  return MonitorTruth(cells_, bus_.chain->deviceCount(), thermistorChannels());
}

void MonitorChainPath::update(double t, const MonitorTruth& truth) {
  MonitorChain& c = *bus_.chain;
  const int perDevice = cfg_.thermistors_per_device;
  const bool unloaded = truth.cell_unloaded_V.size() == truth.cell_V.size();
  const int devices = c.deviceCount();
  for (int d = 0; d < devices; ++d) {
    DeviceAnalog& a = c.analog(d);
    const size_t first = static_cast<size_t>(firstCell_[static_cast<size_t>(d)]);
    a.cell_unloaded_V.resize(unloaded ? a.cell_V.size() : 0);
    // Its cells in the truth (all of them in a stack as built), each array in one pass.
    const size_t n = first < truth.cell_V.size() ? std::min(a.cell_V.size(), truth.cell_V.size() - first) : 0;
    if (n > 0) {
      std::copy_n(truth.cell_V.begin() + static_cast<long>(first), n, a.cell_V.begin());
      if (unloaded) std::copy_n(truth.cell_unloaded_V.begin() + static_cast<long>(first), n, a.cell_unloaded_V.begin());
      std::copy_n(truth.cell_gain_error.begin() + static_cast<long>(first), std::min(n, a.cell_gain_error.size()),
                  a.cell_gain_error.begin());
      std::copy_n(truth.cell_offset_V.begin() + static_cast<long>(first), std::min(n, a.cell_offset_V.size()),
                  a.cell_offset_V.begin());
    }
    for (size_t j = 0; j < a.therm_C.size() && static_cast<int>(j) < perDevice; ++j) {
      const size_t ch = static_cast<size_t>(d * perDevice) + j;
      if (ch >= truth.therm_C.size()) break;
      a.therm_C[j] = truth.therm_C[ch];
      if (j < a.therm_fault.size())
        a.therm_fault[j] = truth.therm_fault[ch];
    }
    a.die_C = (static_cast<size_t>(d) < truth.board_C.size() ? truth.board_C[static_cast<size_t>(d)] : 25.0) +
              cfg_.die_rise_C;
    a.current_A = truth.current_A;
    a.host_opens_balancing = truth.host_opens_balancing;
    c.setCommFault(d, static_cast<size_t>(d) < truth.comm.size() ? truth.comm[static_cast<size_t>(d)]
                                                                : MonitorDeviceFault{});
  }
  c.setBrokenLinkAbove(truth.broken_link_above);
  bus_.advanceTo(t);
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
      for (int k = 0; k < n && cell < cells_; ++k, ++cell) on[cell] = 0, duty[cell] = 1.0;
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
