#include "core/sim/false_fault.hpp"

#include <bms/bms_faults.hpp>
#include <algorithm>
#include <cmath>

#include "core/sim/summary_text.hpp"
#include "core/text_fmt.hpp"

namespace packsim {

namespace {

constexpr double kFloor_V = 0.010, kFloor_C = 2.0, kFloorCurrentRel = 0.01;

bool everyThermistorOnACell(const Scenario& s) {
  for (const ThermistorChannel& ch : s.hardware.thermistors.channels)
    if (ch.site != ThermSite::Cell) return false;
  return !s.hardware.thermistors.channels.empty();
}

}  // namespace

FalseFaultWatch::FalseFaultWatch(const Scenario& s, int parallel) : parallel_(parallel) {
  std::fill(near_, near_ + Q::kQuantities, INFINITY);
  std::fill(lastNear_, lastNear_ + Q::kQuantities, -INFINITY);
  if (s.bms.firmware.library) return;
  using F = bms::FaultId;
  const AdcChannel& adc = s.hardware.cell_adc;
  const MonitorConfig& afe = s.hardware.afe;
  const CurrentSense& cs = s.hardware.current_sense;
  const struct {
    F id;
    Q quantity;
    const char* unit;
  } rows[] = {{F::CellOverVoltage, Q::kVoltsHigh, "V"},
              {F::CellUnderVoltage, Q::kVoltsLow, "V"},
              {F::OverTemperature, Q::kTempHigh, "C"},
              {F::OverCurrentDischarge, Q::kPackDischarge, "A"},
              {F::OverCurrentCharge, Q::kPackCharge, "A"}};
  // The age of a reading at the fault: the BMS's delay, a read-out period and a tick (as
  // LimitWatch allows), and one more read-out period.
  const double readout_s = std::max(s.bms.readout.period_s, s.bms.tick_s);
  for (const auto& r : rows) {
    const ProtectionConfig& p = s.bms.protection(r.id);
    if (!p.enabled) continue;
    if (r.quantity == Q::kTempHigh && !everyThermistorOnACell(s)) continue;
    double tolerance = 0.0;
    if (r.unit[0] == 'V')
      tolerance = std::max(kFloor_V, 0.5e-3 + 0.5 * adc.lsb +
                                         3.0 * (adc.noise_rms + afe.channel_offset_sd_V + afe.channel_gain_sd * p.threshold));
    else if (r.unit[0] == 'C')
      tolerance = kFloor_C;
    else
      tolerance = std::max(kFloorCurrentRel * p.threshold, cs.lsb_A() + 3.0 * cs.noise_A_rms);
    const bool lower = r.quantity == Q::kVoltsLow;
    near_[r.quantity] = lower ? -(p.threshold + tolerance) : p.threshold - tolerance;
    rows_.push_back({static_cast<int>(r.id), r.quantity, p.threshold, tolerance, p.delay_s + 2.0 * readout_s + s.bms.tick_s,
                     r.unit});
    watched_ |= 1u << static_cast<int>(r.id);
  }
}

void FalseFaultWatch::judge(double t, const LimitWatch::CellExtremes& cells, double pack_A,
                            const std::vector<double>& cell_V, const std::vector<double>& cell_C, uint32_t rising,
                            const EventSink& sink) const {
  for (const Row& r : rows_) {
    if (!((rising >> r.fault) & 1u) || t - lastNear_[r.quantity] <= r.window_s + 1e-9) continue;
    const bool volts = r.unit[0] == 'V', current = r.unit[0] == 'A', lower = r.quantity == Q::kVoltsLow;
    // The quantity's value as LimitWatch orders them; the lowest voltage back to a voltage.
    const double value[Q::kQuantities] = {cells.volts.hi, -cells.volts.lo, cells.temps.hi,
                                          -cells.temps.lo, pack_A,         -pack_A};
    const double extreme = lower ? -value[r.quantity] : value[r.quantity];
    std::string what, at;
    if (current) {
      what = r.quantity == Q::kPackCharge ? "the true charge current" : "the true pack current";
      at = "it was " + fmt("%.2f", extreme) + " A at the fault";
    } else {
      const std::vector<double>& v = volts ? cell_V : cell_C;
      const auto cell = lower ? std::min_element(v.begin(), v.end()) : std::max_element(v.begin(), v.end());
      what = volts ? "no cell's true voltage" : "no cell's true temperature";
      at = std::string(lower ? "the lowest" : "the highest") + " at the fault " + fmt(volts ? "%.3f" : "%.1f", extreme) +
           " " + r.unit + ", " + cellName(static_cast<int>(cell - v.begin()) + 1, parallel_);
    }
    const std::string within = volts ? fmt("%.1f", r.tolerance * 1e3) + " mV" : fmt("%.2g", r.tolerance) + " " + r.unit;
    sink(t, std::string(bms::faultName(static_cast<bms::FaultId>(r.fault))) + " at " + fmt("%.2f", t) + " s: " + what +
                (current ? " never came within " : " came within ") + within + " of the " +
                fmt(volts ? "%.3f" : "%g", r.threshold) + " " + r.unit + " limit in the " + fmt("%.2f", r.window_s) +
                " s before (" + at + "): the BMS acted on a reading, not on the cells");
  }
}

}  // namespace packsim
