#include "core/scenario/start_voltage_warning.hpp"

#include <algorithm>
#include <cmath>

#include "core/scenario/provenance.hpp"
#include "core/text_fmt.hpp"
#include "models/cell/ecm.hpp"

namespace packsim {

namespace {

// The cells' lowest and highest initial SOC as the scenario states them (the nominal one
// and pack.cells[] overrides; a seeded spread draws around the nominal one).
struct SocSpan {
  double lo, hi;
  std::string loKey, hiKey;
};

SocSpan initialSocs(const Scenario& s) {
  SocSpan span{s.pack.initial_soc, s.pack.initial_soc, "pack.initial_soc", "pack.initial_soc"};
  for (size_t k = 0; k < s.pack.cell_overrides.size(); ++k) {
    const auto& o = s.pack.cell_overrides[k].initial_soc;
    if (!o) continue;
    const std::string key = "pack.cells[" + std::to_string(k) + "].initial_soc";
    if (*o < span.lo) span.lo = *o, span.loKey = key;
    if (*o > span.hi) span.hi = *o, span.hiKey = key;
  }
  return span;
}

// The pack current of the load's first value (what it is, in words, in `what`); 0 when
// none is known at load time. A power P on n = series
// x parallel cells: each at V = OCV - (P / (n V)) R0, solved for V; NaN when the cells
// cannot give that power at all.
double firstCurrent_A(const Scenario& s, double ocv_V, double r0_ohm, std::string& what) {
  // A charger's current is the BMS's to enable and its CV setpoint's to limit; a vehicle
  // decides its own power.
  if (s.charger.present || s.vehicle.present || s.load.i_A.empty()) return 0.0;
  const double v = s.load.i_A.front();
  const bool power = s.load.quantity == LoadProfile::Quantity::Power_W;
  what = "the load's first " + fmt("%g", v) + (power ? " W" : " A");
  if (!power) return v;
  const double n = static_cast<double>(s.pack.series) * s.pack.parallel;
  const double disc = ocv_V * ocv_V - 4.0 * (v / n) * r0_ohm;
  if (disc < 0.0) return std::nan("");
  return v / n / (0.5 * (ocv_V + std::sqrt(disc))) * s.pack.parallel;
}

struct Limit {
  bool low;  // a lower limit (under-voltage, v_min_V)
  double v;
  std::string text;         // "key = value (origin)"
  std::string consequence;  // what happens at the start
};

std::vector<Limit> limitsOf(const Scenario& s, const Provenance& p) {
  std::vector<Limit> out;
  const CellParams& c = s.pack.cell;
  out.push_back({true, c.v_min_V, p.describe("pack.cell.v_min_V", numberText(c.v_min_V)),
                 "the cell's own limit, where the summary's energy count ends"});
  out.push_back({false, c.v_max_V, p.describe("pack.cell.v_max_V", numberText(c.v_max_V)), "the cell's own limit"});
  if (s.bms.firmware.library) return out;  // a firmware of its own has its own limits
  const struct {
    bms::FaultId id;
    bool low;
    const char* key;
    const char* name;
  } rows[] = {{bms::FaultId::CellUnderVoltage, true, "bms.protections.cell_undervoltage", "under-voltage"},
              {bms::FaultId::CellOverVoltage, false, "bms.protections.cell_overvoltage", "over-voltage"}};
  for (const auto& r : rows) {
    const ProtectionConfig& pc = s.bms.protection(r.id);
    if (!pc.enabled) continue;
    out.push_back({r.low, pc.threshold, p.describe(std::string(r.key) + ".threshold_V", numberText(pc.threshold)),
                   std::string("the BMS's ") + r.name + " protection sees it at its first reading and acts after its " +
                       "delay_ms (" + fmt("%g", pc.delay_s * 1e3) + " ms)"});
  }
  return out;
}

}  // namespace

void checkStartVoltage(const Scenario& s, const Provenance& p, std::vector<std::string>& out) {
  const CellParams& c = s.pack.cell;
  const double t_C = s.pack.initial_temp_C;
  const SocSpan span = initialSocs(s);
  const std::string temp = p.describe("pack.initial_temp_C", numberText(t_C));
  for (const Limit& l : limitsOf(s, p)) {
    const double soc = l.low ? span.lo : span.hi;
    const double ocv_V = ecm::ocv(c, soc, t_C);
    const std::string ocvText = fmt("%.3f", ocv_V) + " V open-circuit at " +
                                p.describe(l.low ? span.loKey : span.hiKey, numberText(soc)) + ", " + temp;
    const std::string past = std::string(l.low ? ", below " : ", above ") + l.text + ": " + l.consequence;
    if (l.low ? ocv_V < l.v : ocv_V > l.v) {
      out.push_back("the cells start at " + ocvText + past);
      continue;
    }
    std::string what;
    const double i_A = firstCurrent_A(s, ocv_V, ecm::r0(c, soc, t_C, 0.0), what);
    if (std::isnan(i_A)) {  // P above n OCV^2 / (4 R0)
      if (l.low)
        out.push_back("the cells cannot give " + what + " at any voltage (at most " +
                      fmt("%.4g", static_cast<double>(s.pack.series) * s.pack.parallel * ocv_V * ocv_V /
                                      (4.0 * ecm::r0(c, soc, t_C, 0.0))) +
                      " W, at half their " + ocvText + ")" + past);
      continue;
    }
    if (i_A == 0.0 || l.low != (i_A > 0.0)) continue;  // the first current moves away from this limit
    const double cell_A = i_A / s.pack.parallel;
    const double r0_ohm = ecm::r0(c, soc, t_C, cell_A);
    // The hysteresis' instantaneous step (M0 against the current's sign) is in the first
    // terminal voltage too; its state starts at 0.
    const double m0_V = c.has_hysteresis ? c.hysteresis_instant_V : 0.0;
    const double v = ocv_V - (cell_A > 0.0 ? m0_V : -m0_V) - cell_A * r0_ohm;
    if (!(l.low ? v < l.v : v > l.v)) continue;
    out.push_back("the cells start at " + fmt("%.3f", v) + " V under " + what + " (" + fmt("%.4g", cell_A) +
                  " A a cell through R0 " + fmt("%.4g", r0_ohm * 1e3) + " mOhm" +
                  (m0_V != 0.0 ? ", hysteresis step " + fmt("%g", m0_V * 1e3) + " mV" : std::string()) + ", from " +
                  ocvText + ")" + past);
  }
}

}  // namespace packsim
