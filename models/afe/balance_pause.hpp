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
// most kMaxPauses, should nobody ask: a ring, so a full one costs no copying).
#pragma once
#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>

namespace packsim {

class BalancePauses {
 public:
  static constexpr size_t kMaxPauses = 256;  // a power of two: the ring's index wraps by a mask

  void add(double from_s, double to_s, uint32_t cells) {
    if (!(to_s > from_s) || cells == 0) return;
    dropEnded();
    if (n_ >= kMaxPauses) head_ = (head_ + 1) & kMask, --n_;
    if (n_ > 0 && from_s < at(n_ - 1).from_s) ordered_ = false;  // (begun before the last: out of order)
    if (n_ > 0 && at(n_ - 1).to_s > from_s) at(n_ - 1).to_s = std::max(at(n_ - 1).from_s, from_s);
    at(n_++) = Pause{from_s, to_s, cells};
    unchecked_ = std::min<size_t>(n_, 2);  // the trimmed last pause and the new one
  }

  double conductingShare(int cell, double t0_s, double t1_s) const {
    asked_s_ = std::max(asked_s_, t0_s);
    if (!(t1_s > t0_s)) return 1.0;
    double open_s = 0.0;
    for (size_t i = 0; i < n_; ++i) {
      const Pause& p = at(i);
      if ((p.cells >> cell) & 1u) open_s += std::max(0.0, std::min(p.to_s, t1_s) - std::max(p.from_s, t0_s));
    }
    return 1.0 - std::min(open_s, t1_s - t0_s) / (t1_s - t0_s);
  }

 private:
  struct Pause {
    double from_s, to_s;
    uint32_t cells;
  };
  static constexpr size_t kMask = kMaxPauses - 1;
  static_assert((kMaxPauses & kMask) == 0, "kMaxPauses must be a power of two");

  Pause& at(size_t i) { return ring_[(head_ + i) & kMask]; }
  const Pause& at(size_t i) const { return ring_[(head_ + i) & kMask]; }

  // Drops the pauses that ended by the last time asked, keeping the others in order.
  // Those already checked against that time still pass: only a new time asked, or the
  // pauses add() changed since (at most the last two), need a look.
  void dropEnded() {
    if (ordered_) return dropEndedInOrder();
    size_t from = n_ - std::min(unchecked_, n_);
    if (asked_s_ != dropped_s_) from = 0, dropped_s_ = asked_s_;
    size_t kept = from;
    for (size_t i = from; i < n_; ++i) {
      if (at(i).to_s <= asked_s_) continue;
      if (kept != i) at(kept) = at(i);  // (none dropped yet, the usual call: nothing to move)
      ++kept;
    }
    n_ = kept;
    unchecked_ = 0;
  }

  // The same while every pause began no earlier than the one before (ordered_: the host's
  // conversions in time order). Each then ends by the next one's start (add() trims it),
  // so they end in order too: those that ended are the oldest, dropped from the front
  // until one has not ended; no pass over the last ones at every add (some 30
  // instructions a conversion). Leaves every pause checked against asked_s_, as
  // dropEnded does.
  void dropEndedInOrder() {
    while (n_ > 0 && at(0).to_s <= asked_s_) head_ = (head_ + 1) & kMask, --n_;
    dropped_s_ = asked_s_;
    unchecked_ = 0;
  }

  std::array<Pause, kMaxPauses> ring_{};
  size_t head_ = 0, n_ = 0;  // the pauses, oldest first: ring_[(head_ + i) & kMask], i < n_
  size_t unchecked_ = 0;     // the last ones not yet checked against dropped_s_
  bool ordered_ = true;      // every pause added began no earlier than the one before it
  double dropped_s_ = -std::numeric_limits<double>::infinity();  // the asked time dropEnded() last used
  mutable double asked_s_ = -std::numeric_limits<double>::infinity();
};

}  // namespace packsim
