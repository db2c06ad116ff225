// The firmware's state-estimation configuration from the scenario's `bms.soc` section:
// what a firmware engineer flashes. Values the scenario leaves out come from the pack's
// cell as a datasheet would give them (OCV and R0 sampled at 11 SOC points, the first
// RC pair), never from the simulated truth of individual cells. R0 is sampled at
// `r0_ref_temp_C` and corrected by an Arrhenius factor on the measured temperature: the
// cell's own factor, or for an R0 table over temperature a fit of it.
#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "core/sim/bms_image.hpp"

namespace packsim {

namespace {

// R0's Arrhenius constant as a datasheet gives it: 0 for an R0 that does not depend on
// temperature, the curve's own factor, or for an R0 table over temperature the
// least-squares fit through the reference of ln(R0(soc,T) / R0(soc,T_ref)) =
// K·(1/T_K − 1/T_ref_K) over the table's grid temperatures and the firmware's SOC points.
double r0ArrheniusOfCell_K(const CellParams& cell, int points, double ref_C) {
  const Curve& r0 = cell.r0_ohm;
  if (!r0.dependsOnTemperature()) return 0.0;
  if (r0.kind != Curve::Kind::Table2D) return r0.arrhenius_K;
  double sxy = 0.0, sxx = 0.0;
  for (const double t_C : r0.temps_C()) {
    const double x = 1.0 / (t_C + kZeroCelsius_K) - 1.0 / (ref_C + kZeroCelsius_K);
    for (int i = 0; i < points; ++i) {
      const double soc = i / double(points - 1);
      const double at = ecm::r0(cell, soc, t_C), ref = ecm::r0(cell, soc, ref_C);
      if (!(at > 0.0) || !(ref > 0.0)) continue;
      sxy += x * std::log(at / ref);
      sxx += x * x;
    }
  }
  return sxx > 0.0 ? std::clamp(sxy / sxx, 0.0, 20000.0) : 0.0;
}

}  // namespace

void setSocConfig(bms::SocConfig& c, const Scenario& s) {
  const CellParams& cell = s.pack.cell;
  const SocEstimationSettings& e = s.bms.soc_estimation;
  const double parallel = s.pack.parallel;
  const double cellCapacity_Ah = e.cell_capacity_Ah >= 0.0 ? e.cell_capacity_Ah : cell.capacity_Ah;
  c.capacity_mAh = static_cast<float>(cellCapacity_Ah * parallel * 1e3);
  const int points = e.ocv_V.empty() ? 11 : static_cast<int>(e.ocv_V.size());
  c.ocvPoints = static_cast<uint8_t>(points);
  uint16_t prev = 0;
  for (int i = 0; i < points; ++i) {
    const double v = e.ocv_V.empty() ? ecm::ocv(cell, i / double(points - 1)) : e.ocv_V[static_cast<size_t>(i)];
    uint16_t mv = static_cast<uint16_t>(std::clamp(std::lround(v * 1e3), 0L, 65535L));
    mv = std::max<uint16_t>(mv, prev);  // the table must not fall
    c.ocv_mV[i] = prev = mv;
  }
  // rest_ms, restCurrent_mA, estimator, sohMinDeltaSoc and the EKF's noise: settings rows.
  const bool hasRc = !cell.rc.empty();
  const double r1_ohm = e.cell_r1_ohm >= 0.0 ? e.cell_r1_ohm : hasRc ? cell.rc[0].r_ohm : 0.0;
  const double tau1_s = e.tau1_s > 0.0 ? e.tau1_s : hasRc ? cell.rc[0].tau_s() : 30.0;
  bms::EkfConfig& k = c.ekf;
  for (int i = 0; i < points; ++i) {  // a group: the cells in parallel
    const double soc = i / double(points - 1);
    const double r0_ohm = e.cell_r0_ohm.empty()       ? ecm::r0(cell, soc, e.r0_ref_temp_C)
                          : e.cell_r0_ohm.size() == 1 ? e.cell_r0_ohm[0]
                                                      : e.cell_r0_ohm[static_cast<size_t>(i)];
    k.r0_mOhm[i] = static_cast<float>(r0_ohm / parallel * 1e3);
  }
  k.r0RefTemp_C = static_cast<float>(e.r0_ref_temp_C);
  k.r0ArrheniusK = static_cast<float>(e.r0_arrhenius_K >= 0.0 ? e.r0_arrhenius_K
                                                              : r0ArrheniusOfCell_K(cell, points, e.r0_ref_temp_C));
  k.r1_mOhm = static_cast<float>(r1_ohm / parallel * 1e3);
  k.tau1_s = static_cast<float>(tau1_s);
  k.initialSoc = static_cast<float>(e.initial_soc);
  for (size_t i = 0; i < e.display_bars_V.size() && i + 1 < bms::kDisplayBars; ++i)
    c.displayBars_mV[i] = static_cast<uint16_t>(std::lround(e.display_bars_V[i] * 1e3));
}

}  // namespace packsim
