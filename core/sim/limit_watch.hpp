// Cells past a protection limit the BMS has not seen (issue 28): compares the truth
// (every cell's voltage and temperature, the pack current) with the protection table's
// thresholds each tick. An episode starts when a cell passes a limit while its
// protection row is not active in the BMS, and ends when the row becomes active (the
// BMS saw it), when the cell comes back within the limit (never seen) or at the end of
// the run. "Past" is past by more than half the BMS's reading step: the firmware reads
// whole mV of a converter code (and 0.1 C), rounded, so a cell 0.2 mV under 2.500 V reads
// 2500 mV -- at a 1 mV/s discharge that is a second no BMS of that resolution can see. An episode the BMS is built to take -- no longer than the protection's own
// delay plus one read-out period and one tick (a 20 ms dip under a 500 ms debounce) --
// is no miss and is only counted. Each (cell, limit)'s first longer episode and any
// later longer one become a
// `limit_unseen` event: "overtemperature: cell 74 (group 19) above the 60 C limit from
// 511.00 s, unseen by the BMS for 499.00 s (max 86.6 C)".
#pragma once
#include <cmath>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "core/scenario/scenario.hpp"

namespace packsim {

class LimitWatch {
 public:
  // Off (nothing watched) for a library firmware: its limits are its own, not the table's.
  LimitWatch(const Scenario& s, int cells, int parallel);

  using EventSink = std::function<void(double t, const std::string& detail)>;
  // The lowest and highest of some values, NaN skipped (init at the infinities, taken
  // only by a comparison that is true): some value is above a limit exactly when the
  // highest is, below it exactly when the lowest is.
  struct Extremes {
    double lo = INFINITY, hi = -INFINITY;
    void take(double x) {
      lo = x < lo ? x : lo;  // minsd / maxsd: a NaN x leaves them as they are
      hi = x > hi ? x : hi;
    }
    void take(const std::vector<double>& v);
  };
  // A tick's extremes of the cell voltages and temperatures, for a caller that passes
  // over them anyway (RunTracker::tick): the usual tick's test then reads no value again.
  struct CellExtremes {
    Extremes volts, temps;
  };
  // The quantities a protection of the table watches, each as "highest > bound": a lower
  // limit's values negated (negation is exact; a NaN pack current passes neither form).
  enum Quantity { kVoltsHigh, kVoltsLow, kTempHigh, kTempLow, kPackDischarge, kPackCharge, kQuantities };
  // Bit q set where quantity q's value this tick -- (volts.hi, -volts.lo, temps.hi,
  // -temps.lo, pack_A, -pack_A)[q] -- is above bound[q] (at or above it with OrEqual; an
  // unwatched quantity's bound is +inf). Two quantities per compare with SSE2, the high
  // lane's sign flipped being the negation.
  template <bool OrEqual>
  static unsigned pastMask(const CellExtremes& cells, double pack_A, const double* bound) {
#if defined(__SSE2__)
    static_assert(kVoltsLow == kVoltsHigh + 1 && kTempHigh == 2 && kTempLow == 3 && kPackCharge == kPackDischarge + 1,
                  "LimitWatch: the quantities go in (high, low) pairs");
    const __m128d negateHigh = _mm_set_pd(-0.0, 0.0);
    const auto past = [&](double high, double low, int q) {
      const __m128d v = _mm_xor_pd(_mm_set_pd(low, high), negateHigh);
      const __m128d b = _mm_loadu_pd(bound + q);
      return static_cast<unsigned>(_mm_movemask_pd(OrEqual ? _mm_cmpge_pd(v, b) : _mm_cmpgt_pd(v, b))) << q;
    };
    return past(cells.volts.hi, cells.volts.lo, kVoltsHigh) | past(cells.temps.hi, cells.temps.lo, kTempHigh) |
           past(pack_A, pack_A, kPackDischarge);
#else
    const double value[kQuantities] = {cells.volts.hi, -cells.volts.lo, cells.temps.hi,
                                       -cells.temps.lo, pack_A,         -pack_A};
    unsigned mask = 0;
    for (int q = 0; q < kQuantities; ++q) mask |= static_cast<unsigned>(OrEqual ? value[q] >= bound[q] : value[q] > bound[q]) << q;
    return mask;
#endif
  }
  // One tick: truth (cell voltages V, temperatures C, pack current A, + discharges) and
  // the BMS's active fault bits; `known`: cell_V's and cell_C's extremes, or null (taken here).
  // (The usual tick -- no episode open, no value past any watched threshold -- returns
  // here, inline: the call and anyPast's cost some 45 instructions a tick.)
  void tick(double t, const std::vector<double>& cell_V, const std::vector<double>& cell_C, double pack_A,
            uint32_t faultActive, const EventSink& sink, const CellExtremes* known = nullptr) {
    if (openTotal_ == 0 && known && noneAbove(*known, pack_A)) return;
    tickRows(t, cell_V, cell_C, pack_A, faultActive, sink, known);
  }
  // Closes every open episode at the end of the run.
  void finish(double t, const EventSink& sink);
  double longestUnseen_s() const { return longest_s_; }
  long shortExcursions() const { return short_; }  // episodes within allowed_s (not events)
  const std::string& longestUnseen() const { return longest_; }

 private:
  struct Limit {
    int fault;          // bms::FaultId
    const char* what;   // "above the 60 C limit"
    bool above;
    double threshold;
    const char* unit;
    bool perCell;       // false: the pack current (one "cell" slot)
    double allowed_s;   // delay + read-out period + tick: what the BMS takes by design
    double step;        // the BMS's reading step's half: a value closer to the limit reads as the limit
    // The threshold passed by `step`: where an episode starts.
    double watchAt() const { return above ? threshold + step : threshold - step; }
  };
  struct Episode {
    double from_s = -1.0;  // < 0: none open
    double extreme = 0.0;
    double reported_s = -1.0;  // longest unseen time reported so far (< 0: none yet)
  };
  void close(size_t li, size_t c, double t, bool seen, bool atEnd, const EventSink& sink);
  std::string subject(size_t li, size_t c) const;

  std::vector<Limit> limits_;
  std::vector<std::vector<Episode>> ep_;  // [limit][cell]
  std::vector<size_t> open_;              // [limit]: episodes open (from_s >= 0)
  size_t openTotal_ = 0;                  // over every limit
  // The usual tick's test (anyPast), per quantity: its highest value (of the values or of
  // their negatives) against the threshold (negated for a lower limit), unless the row's
  // fault bit is active. One protection row per quantity at most; a quantity no row
  // watches has threshold +inf (no value is above it) and no bit.
  double threshold_[kQuantities] = {INFINITY, INFINITY, INFINITY, INFINITY, INFINITY, INFINITY};
  uint32_t faultBit_[kQuantities] = {};
  bool anyPast(const CellExtremes& cells, double pack_A, uint32_t faultActive) const;
  // No quantity above its threshold at all, whatever the fault bits (anyPast's first
  // test): then anyPast is false.
  bool noneAbove(const CellExtremes& cells, double pack_A) const { return pastMask<false>(cells, pack_A, threshold_) == 0; }
  void tickRows(double t, const std::vector<double>& cell_V, const std::vector<double>& cell_C, double pack_A,
                uint32_t faultActive, const EventSink& sink, const CellExtremes* known);
  static CellExtremes extremesOf(const std::vector<double>& cell_V, const std::vector<double>& cell_C);
  int parallel_;
  double longest_s_ = 0.0;
  long short_ = 0;
  std::string longest_;
};

}  // namespace packsim
