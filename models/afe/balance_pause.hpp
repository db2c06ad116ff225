// The times a monitor device holds its balancing switches open for a conversion: the
// part's own pause (the LTC681x with DCP = 0) or the host's (bms.balancing.measure_paused:
// the host opens the switches around each conversion it starts). A switch held on
// conducts for the rest of the time, so its average current is I_bal times the share
// conductingShare() gives (the plant's balance duty, core/sim/plant.hpp).
//
//   add(from, to, cells)          cells (bit i: the device's cell i) are open over [from, to)
//   conductingShare(i, t0, t1)    1 - (time of [t0, t1) cell i is open) / (t1 - t0)
//
// Pauses of one device do not overlap (a conversion ends before the next starts, or is
// cut short by it: add() trims the previous one). The host asks tick by tick, t0 never
// decreasing: add() drops the pauses that ended before the last t0 asked (and keeps at
// most kMaxPauses, should nobody ask).
#pragma once
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

namespace packsim {

class BalancePauses {
 public:
  static constexpr size_t kMaxPauses = 256;

  void add(double from_s, double to_s, uint32_t cells) {
    if (!(to_s > from_s) || cells == 0) return;
    pauses_.erase(std::remove_if(pauses_.begin(), pauses_.end(), [&](const Pause& p) { return p.to_s <= asked_s_; }),
                  pauses_.end());
    if (pauses_.size() >= kMaxPauses) pauses_.erase(pauses_.begin());
    if (!pauses_.empty() && pauses_.back().to_s > from_s) pauses_.back().to_s = std::max(pauses_.back().from_s, from_s);
    pauses_.push_back({from_s, to_s, cells});
  }

  double conductingShare(int cell, double t0_s, double t1_s) const {
    asked_s_ = std::max(asked_s_, t0_s);
    if (!(t1_s > t0_s)) return 1.0;
    double open_s = 0.0;
    for (const Pause& p : pauses_)
      if ((p.cells >> cell) & 1u) open_s += std::max(0.0, std::min(p.to_s, t1_s) - std::max(p.from_s, t0_s));
    return 1.0 - std::min(open_s, t1_s - t0_s) / (t1_s - t0_s);
  }

 private:
  struct Pause {
    double from_s, to_s;
    uint32_t cells;
  };
  std::vector<Pause> pauses_;
  mutable double asked_s_ = -std::numeric_limits<double>::infinity();
};

}  // namespace packsim
