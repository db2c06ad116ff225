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

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "core/scenario/scenario.hpp"

namespace packsim {

class FalseFaultWatch {
 public:
  // Off (nothing watched) for a library firmware: its limits are its own, not the table's.
  FalseFaultWatch(const Scenario& s, int parallel);

  using EventSink = std::function<void(double t, const std::string& detail)>;
  // One tick: the tick's extremes of the true cell voltages, its highest temperature, the pack
  // current (A, + discharge), the cells' values (for naming one) and the BMS's active
  // fault bits.
  void tick(double t, double voltsLo, double voltsHi, double tempsHi, double pack_A,
            const std::vector<double>& cell_V, const std::vector<double>& cell_C, uint32_t faultActive,
            const EventSink& sink) {
    if (rows_.empty()) return;
    // The quantities near their limits as one mask, stored only when one is (rarely):
    // two at a time with SSE2, some 30 instructions a tick less than one by one.
    const unsigned near = nearMask(voltsLo, voltsHi, tempsHi, pack_A);
    if (near) noteNear(t, near);
    const uint32_t rising = faultActive & ~lastActive_ & watched_;
    lastActive_ = faultActive;
    if (rising) {
      const double value[kQuantities] = {voltsHi, -voltsLo, tempsHi, pack_A, -pack_A};
      judge(t, value, cell_V, cell_C, rising, sink);
    }
  }

 private:
  enum Quantity { kVoltsHigh, kVoltsLow, kTempHigh, kPackDischarge, kPackCharge, kQuantities };
  struct Row {
    int fault;  // bms::FaultId
    int quantity;
    double threshold, tolerance, window_s;
    const char* unit;
  };
  // Bit q: quantity q's value (voltsHi, -voltsLo, tempsHi, pack_A, -pack_A) at or past
  // near_[q] (a NaN is not).
  unsigned nearMask(double voltsLo, double voltsHi, double tempsHi, double pack_A) const {
#if defined(__SSE2__)
    const __m128d negateHigh = _mm_set_pd(-0.0, 0.0);
    const auto atOrPast = [&](double low, double high, int q) {
      return static_cast<unsigned>(_mm_movemask_pd(_mm_cmpge_pd(_mm_set_pd(high, low), _mm_loadu_pd(near_ + q))));
    };
    const __m128d v = _mm_xor_pd(_mm_set_pd(voltsLo, voltsHi), negateHigh);
    return static_cast<unsigned>(_mm_movemask_pd(_mm_cmpge_pd(v, _mm_loadu_pd(near_)))) |
           atOrPast(tempsHi, pack_A, kTempHigh) << kTempHigh | atOrPast(-pack_A, 0.0, kPackCharge) << kPackCharge;
#else
    const double value[kQuantities] = {voltsHi, -voltsLo, tempsHi, pack_A, -pack_A};
    unsigned near = 0;
    for (int q = 0; q < kQuantities; ++q) near |= static_cast<unsigned>(value[q] >= near_[q]) << q;
    return near;
#endif
  }
  void noteNear(double t, unsigned near) {
    for (int q = 0; q < kQuantities; ++q)
      if ((near >> q) & 1u) lastNear_[q] = t;
  }
  void judge(double t, const double* value, const std::vector<double>& cell_V, const std::vector<double>& cell_C,
             uint32_t rising, const EventSink& sink) const;
  std::vector<Row> rows_;
  // Per quantity: where its value counts as at the limit (threshold less the tolerance,
  // negated for a lower limit; +inf unwatched) and the last tick it was (-inf: never).
  double near_[kQuantities + 1];  // one more, +inf: the unused lane of the last pair
  double lastNear_[kQuantities];
  uint32_t watched_ = 0, lastActive_ = 0;
  int parallel_;
};

}  // namespace packsim
