// Faults the BMS raised on readings the cells did not have: the mirror of LimitWatch.
// When a protection of the table (cell over/under-voltage, over-temperature, over-current)
// becomes active, the truth should have been at its limit within the time the BMS took to
// judge it (its delay, a read-out period and a tick, and one more read-out for the age
// of a reading). If no cell came within a reading's honest error of the limit in that
// time -- a channel gain or offset fault, a miscalibrated converter, a stuck reading --
// the fault is a false one, and a `false_fault` event says so, with the truth's extreme
// at that instant: "cell_overvoltage at 121.50 s: no cell's true voltage came within
// 10.0 mV of the 4.250 V limit in the 1.30 s before (the highest at the fault 4.031 V,
// cell 25 (group 7)): the BMS acted on a reading, not on the cells".
// The honest error is the reading's step and three times its noise, at least 10 mV,
// 2 C or 1 % of a current limit: a trip on a real limit is never called false for the
// rounding or noise of its reading. Over-temperature is judged only where every
// thermistor sits on a cell (one on a FET or a board reads no cell's temperature).
#pragma once
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "core/scenario/scenario.hpp"
#include "core/sim/limit_watch.hpp"

namespace packsim {

class FalseFaultWatch {
 public:
  // Off (nothing watched) for a library firmware: its limits are its own, not the table's.
  FalseFaultWatch(const Scenario& s, int parallel);

  using EventSink = std::function<void(double t, const std::string& detail)>;
  using Q = LimitWatch::Quantity;
  // One tick: the tick's extremes of the true cell voltages and temperatures, the pack
  // current (A, + discharge), the cells' values (for naming one) and the BMS's active
  // fault bits.
  void tick(double t, const LimitWatch::CellExtremes& cells, double pack_A, const std::vector<double>& cell_V,
            const std::vector<double>& cell_C, uint32_t faultActive, const EventSink& sink) {
    if (rows_.empty()) return;
    // The quantities near their limits as one mask (LimitWatch's, at or past), stored only
    // when one is (rarely).
    const unsigned near = LimitWatch::pastMask<true>(cells, pack_A, near_);
    if (near) noteNear(t, near);
    const uint32_t rising = faultActive & ~lastActive_ & watched_;
    lastActive_ = faultActive;
    if (rising) judge(t, cells, pack_A, cell_V, cell_C, rising, sink);
  }

 private:
  struct Row {
    int fault;  // bms::FaultId
    Q quantity;
    double threshold, tolerance, window_s;
    const char* unit;
  };
  void noteNear(double t, unsigned near) {
    for (int q = 0; q < Q::kQuantities; ++q)
      if ((near >> q) & 1u) lastNear_[q] = t;
  }
  void judge(double t, const LimitWatch::CellExtremes& cells, double pack_A, const std::vector<double>& cell_V,
             const std::vector<double>& cell_C, uint32_t rising, const EventSink& sink) const;
  std::vector<Row> rows_;
  // Per quantity (LimitWatch's): where its value counts as at the limit (threshold less
  // the tolerance, negated for a lower limit; +inf unwatched) and the last tick it was
  // (-inf: never).
  double near_[Q::kQuantities];
  double lastNear_[Q::kQuantities];
  uint32_t watched_ = 0, lastActive_ = 0;
  int parallel_;
};

}  // namespace packsim
