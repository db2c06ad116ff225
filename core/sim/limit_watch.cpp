#include "core/sim/limit_watch.hpp"

#include <bms/bms_faults.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/sim/summary_text.hpp"
#include "core/text_fmt.hpp"

namespace packsim {

LimitWatch::LimitWatch(const Scenario& s, int cells, int parallel) : parallel_(parallel) {
  if (s.bms.firmware.library) return;
  using F = bms::FaultId;
  const struct {
    F id;
    bool above;
    const char* unit;
    bool perCell;
  } rows[] = {{F::CellOverVoltage, true, "V", true},
              {F::CellUnderVoltage, false, "V", true},
              {F::OverTemperature, true, "C", true},
              {F::OverCurrentDischarge, true, "A", false},
              {F::OverCurrentCharge, true, "A", false}};
  const double latency_s = std::max(s.bms.readout.period_s, s.bms.tick_s) + s.bms.tick_s;
  // Half the reading step (the firmware's whole mV of the part's code, its 0.1 C): nearer
  // the limit than this a value may read as the limit itself.
  const double voltStep = 0.5e-3 + 0.5 * s.hardware.cell_adc.lsb, tempStep = 0.05;
  for (const auto& r : rows) {
    const ProtectionConfig& p = s.bms.protection(r.id);
    if (!p.enabled) continue;
    const double step = !r.perCell ? 0.0 : r.unit[0] == 'V' ? voltStep : tempStep;
    limits_.push_back({static_cast<int>(r.id), r.above ? "above" : "below", r.above, p.threshold, r.unit, r.perCell,
                       p.delay_s + latency_s, step});
    const bool charge = r.id == F::OverCurrentCharge;
    const int quantity = !r.perCell ? (charge ? kPackCharge : kPackDischarge)
                         : r.unit[0] == 'V' ? (r.above ? kVoltsHigh : kVoltsLow)
                                            : (r.above ? kTempHigh : kTempLow);
    threshold_[quantity] = r.above ? limits_.back().watchAt() : -limits_.back().watchAt();
    faultBit_[quantity] = 1u << static_cast<int>(r.id);
    ep_.emplace_back(static_cast<size_t>(r.perCell ? cells : 1));
    open_.push_back(0);
  }
}

std::string LimitWatch::subject(size_t li, size_t c) const {
  return limits_[li].perCell ? cellName(static_cast<int>(c) + 1, parallel_) : std::string("pack current");
}

void LimitWatch::close(size_t li, size_t c, double t, bool seen, bool atEnd, const EventSink& sink) {
  Episode& e = ep_[li][c];
  const Limit& l = limits_[li];
  const double unseen_s = t - e.from_s;
  const double from_s = e.from_s;
  e.from_s = -1.0;
  --open_[li];
  --openTotal_;
  if (unseen_s <= l.allowed_s + 1e-9) {  // within the BMS's own delay and latency: no miss
    ++short_;
    return;
  }
  if (e.reported_s >= 0.0 && unseen_s <= e.reported_s) return;  // not longer than one already reported
  e.reported_s = unseen_s;
  const bool volts = l.unit[0] == 'V';
  const char* f = volts ? "%.4f" : "%.1f";
  const std::string by = l.step <= 0.0 ? ""
                         : volts       ? "more than " + fmt("%.2g", l.step * 1e3) + " mV "
                                       : "more than " + fmt("%.2g", l.step) + " C ";
  std::string d = std::string(bms::faultName(static_cast<bms::FaultId>(l.fault))) + ": " + subject(li, c) + " " + by +
                  l.what + " the " + fmt(volts ? "%.3f" : "%g", l.threshold) + " " + l.unit + " limit from " +
                  fmt("%.2f", from_s) + " s, ";
  if (seen)
    d += "unseen by the BMS for " + fmt("%.2f", unseen_s) + " s";
  else if (atEnd)
    d += "unseen by the BMS to the end of the run (" + fmt("%.2f", unseen_s) + " s)";
  else
    d += "back within it at " + fmt("%.2f", t) + " s, never seen by the BMS (" + fmt("%.2f", unseen_s) + " s)";
  d += std::string(" (") + (l.above ? "max " : "min ") + fmt(f, e.extreme) + " " + l.unit + ")";
  if (unseen_s > longest_s_) {
    longest_s_ = unseen_s;
    longest_ = d;
  }
  sink(t, d);
}

// With SSE2 two values at a time: minpd(x, lo) is (x < lo ? x : lo) per lane, the same
// NaN-skipping choice as take(double).
void LimitWatch::Extremes::take(const std::vector<double>& v) {
  const size_t n = v.size();
  size_t c = 0;
#if defined(__SSE2__)
  if (n >= 2) {
    __m128d lo2 = _mm_set1_pd(INFINITY), hi2 = _mm_set1_pd(-INFINITY);
    for (; c + 2 <= n; c += 2) {
      const __m128d x = _mm_loadu_pd(v.data() + c);
      lo2 = _mm_min_pd(x, lo2);
      hi2 = _mm_max_pd(x, hi2);
    }
    double l[2], h[2];
    _mm_storeu_pd(l, lo2);
    _mm_storeu_pd(h, hi2);
    for (int k = 0; k < 2; ++k) {
      if (l[k] < lo) lo = l[k];
      if (h[k] > hi) hi = h[k];
    }
  }
#endif
  for (; c < n; ++c) take(v[c]);
}

LimitWatch::CellExtremes LimitWatch::extremesOf(const std::vector<double>& cell_V, const std::vector<double>& cell_C) {
  CellExtremes e;
  e.volts.take(cell_V);
  e.temps.take(cell_C);
  return e;
}

// Whether some value is past a limit whose row is not active: from each quantity's
// extremes, taken once a tick. Every check reads as "highest > threshold": a lower
// limit as -lowest > -threshold (negation is exact; a NaN pack current fails both forms).
bool LimitWatch::anyPast(const CellExtremes& cells, double pack_A, uint32_t faultActive) const {
  const Extremes &volts = cells.volts, &temps = cells.temps;
  // The usual tick first (some 25 instructions less than the row-by-row test below,
  // which decides the rest).
  if (noneAbove(cells, pack_A)) return false;
  const double highest[kQuantities] = {volts.hi, -volts.lo, temps.hi, -temps.lo, pack_A, -pack_A};
  // Every quantity, unrolled without a branch each (an unwatched one's +inf threshold
  // never passes): about half the instructions of a loop over the watched rows.
  bool past = false;
#pragma GCC unroll 8
  for (int q = 0; q < kQuantities; ++q) past |= ((faultActive & faultBit_[q]) == 0) & (highest[q] > threshold_[q]);
  return past;
}

void LimitWatch::tickRows(double t, const std::vector<double>& cell_V, const std::vector<double>& cell_C, double pack_A,
                          uint32_t faultActive, const EventSink& sink, const CellExtremes* known) {
  // The usual tick: no episode open, and no value past a limit whose row is not active
  // (none opens): nothing to do.
  if (openTotal_ == 0) {
    if (limits_.empty()) return;  // off: nothing watched (no episode ever opens)
    if (!(known ? anyPast(*known, pack_A, faultActive) : anyPast(extremesOf(cell_V, cell_C), pack_A, faultActive)))
      return;
  }
  for (size_t li = 0; li < limits_.size(); ++li) {
    const Limit& l = limits_[li];
    const bool active = (faultActive >> l.fault) & 1u;
    const bool charge = l.fault == static_cast<int>(bms::FaultId::OverCurrentCharge);
    const double packValue = charge ? -pack_A : pack_A;
    const double* values = !l.perCell ? &packValue : l.unit[0] == 'V' ? cell_V.data() : cell_C.data();
    const size_t n = ep_[li].size();
    const double at = l.watchAt();
    // No episode open: one opens only where a value is past the limit while the row is
    // not active.
    if (open_[li] == 0) {
      if (active) continue;
      bool past = false;
      for (size_t c = 0; c < n; ++c) past |= l.above ? values[c] > at : values[c] < at;
      if (!past) continue;
    }
    for (size_t c = 0; c < n; ++c) {
      const double v = values[c];
      const bool past = l.above ? v > at : v < at;
      Episode& e = ep_[li][c];
      if (e.from_s < 0.0) {
        if (past && !active) {
          e.from_s = t;
          e.extreme = v;
          ++open_[li];
          ++openTotal_;
        }
        continue;
      }
      if (past) e.extreme = l.above ? std::max(e.extreme, v) : std::min(e.extreme, v);
      if (active) close(li, c, t, true, false, sink);
      else if (!past) close(li, c, t, false, false, sink);
    }
  }
}

void LimitWatch::finish(double t, const EventSink& sink) {
  for (size_t li = 0; li < limits_.size(); ++li)
    for (size_t c = 0; c < ep_[li].size(); ++c)
      if (ep_[li][c].from_s >= 0.0) close(li, c, t, false, true, sink);
}

}  // namespace packsim
