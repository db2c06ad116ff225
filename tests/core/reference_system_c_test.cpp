// Reference system C as its team measured it: the NCR18650 preset's OCV, relaxation and
// the bench pack's thermal coupling reproduce the bench figures.
//   - loaded 3.6 V at 1.372 Ah and 3.5 V at 1.933 Ah discharged at 0.2C (0.59 A);
//   - a cell near 3.58 V bled through 47 ohm for 2 h falls only ~0.02 V;
//   - the OCV read after a 10-minute rest has visibly relaxed (RC pair);
//   - a 1C discharge spreads the cell temperatures by ~0.6 C.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "core/sim/simulation.hpp"
#include "test_support.hpp"

namespace packsim {
namespace {

// One preset cell, no measurement noise, no spread; the BMS only watches.
std::string oneCell(double initialSoc, const std::string& load, double duration_s) {
  return "name: c_cell\nseed: 1\npack:\n  series: 1\n  initial_soc: " + std::to_string(initialSoc) +
         "\n  cell: {preset: ncr18650_3p1Ah}\n"
         "hardware:\n  cell_adc: {lsb_uV: 100, bits: 16, noise_mV_rms: 0}\n  thermistors: {at_groups: [1]}\n"
         "  current_sense: {shunt_ohm: 0.005, amp_gain: 20, noise_A_rms: 0}\n"
         "bms:\n  tick_ms: 1000\n  protections:\n    cell_undervoltage: {threshold_V: 2.5, delay_ms: 2000}\n"
         "    overcurrent_discharge: {threshold_A: 10, delay_ms: 200}\n    overcurrent_charge: {threshold_A: 2, delay_ms: 200}\n"
         "load: " + load + "\nrun: {duration_s: " + std::to_string(duration_s) + "}\noutput: {interval_s: 1}\n";
}

// Linear interpolation of y over an increasing x.
double interp(const std::vector<double>& x, const std::vector<double>& y, double at) {
  const auto it = std::lower_bound(x.begin(), x.end(), at);
  if (it == x.begin()) return y.front();
  if (it == x.end()) return y.back();
  const size_t i = static_cast<size_t>(it - x.begin());
  return y[i - 1] + (y[i] - y[i - 1]) * (at - x[i - 1]) / (x[i] - x[i - 1]);
}

TEST(ReferenceSystemC, LoadedVoltageAtTheTeamsTwoPointsOfThe02CDischarge) {
  const RunResult r = runScenario(test::scenarioFromYaml(oneCell(1.0, "{current_A: 0.59}", 14000)));
  const Recording& rec = r.rec;
  std::vector<double> ah(rec.samples(), 0.0);
  for (size_t k = 1; k < rec.samples(); ++k)
    ah[k] = ah[k - 1] + 0.5 * (rec.pack_current_A[k] + rec.pack_current_A[k - 1]) * (rec.time_s[k] - rec.time_s[k - 1]) / 3600.0;
  // 0.1 V between them is the team's 0.561 Ah per 0.1 V; 5 mV is about 3 % of that slope.
  EXPECT_NEAR(interp(ah, rec.cell_voltage_V, 1.372), 3.600, 0.005);
  EXPECT_NEAR(interp(ah, rec.cell_voltage_V, 1.933), 3.500, 0.005);
}

TEST(ReferenceSystemC, TwoHoursOfBleedingThrough47OhmLowersA358VCellByAbout20mV) {
  // OCV 3.588 V (1.75 Ah discharged): the cell reads ~3.58 V under the 76 mA bleed.
  const double soc = 1.0 - 1.75 / 3.1;
  const RunResult r = runScenario(test::scenarioFromYaml(oneCell(soc, "{current_A: 0.0762}", 7500)));
  const Recording& rec = r.rec;
  const double v0 = interp(rec.time_s, rec.cell_voltage_V, 300.0);  // the RC pair has settled
  const double v1 = interp(rec.time_s, rec.cell_voltage_V, 300.0 + 7200.0);
  EXPECT_NEAR(v0, 3.58, 0.01);
  EXPECT_GT(v0 - v1, 0.012);
  EXPECT_LT(v0 - v1, 0.030);
}

TEST(ReferenceSystemC, TheVoltageRelaxesVisiblyOverATenMinuteRest) {
  // 0.2C for 1.372 Ah, then rest: an instant step of I·R0, then the RC pair relaxes.
  const double t_stop = 1.372 * 3600.0 / 0.59;
  const std::string load = "{segments: [{current_A: 0.59, duration_s: " + std::to_string(t_stop) +
                           "}, {current_A: 0.0, duration_s: 4000}]}";
  const RunResult r = runScenario(test::scenarioFromYaml(oneCell(1.0, load, t_stop + 4000.0)));
  const Recording& rec = r.rec;
  const double vLoaded = interp(rec.time_s, rec.cell_voltage_V, t_stop - 1.0);
  const double vStep = interp(rec.time_s, rec.cell_voltage_V, t_stop + 1.0);
  const double v10min = interp(rec.time_s, rec.cell_voltage_V, t_stop + 600.0);
  const double vRested = interp(rec.time_s, rec.cell_voltage_V, t_stop + 3900.0);
  EXPECT_NEAR(vStep - vLoaded, 0.59 * (0.1034 - 0.015), 0.002);  // R0 = Rint(1.372 Ah) - R1
  EXPECT_GT(v10min - vStep, 0.005);                                // relaxation visible
  EXPECT_NEAR(vRested - v10min, 0.59 * 0.015 * std::exp(-600.0 / 200.0), 0.001);  // 95 % relaxed in 10 min
}

TEST(ReferenceSystemC, A1CDischargeSpreadsTheCellTemperaturesByAboutSixTenthsOfADegree) {
  Scenario s = loadScenarioFile(test::scenarioDir() + "/bench_6s_ncr18650_2C.yaml");
  s.load = test::scenarioFromYaml(oneCell(1.0, "{current_A: 3.1}", 10)).load;
  s.run.duration_s = 4000.0;
  const RunResult r = runScenario(s);
  ASSERT_TRUE(r.summary.tripped);
  const Recording& rec = r.rec;
  const size_t n = static_cast<size_t>(s.pack.series);
  double spread = 0.0;
  for (size_t k = 0; k < rec.samples(); ++k) {
    const auto first = rec.cell_temp_C.begin() + static_cast<long>(k * n);
    const auto [lo, hi] = std::minmax_element(first, first + static_cast<long>(n));
    spread = std::max(spread, *hi - *lo);
  }
  EXPECT_GT(spread, 0.4);
  EXPECT_LT(spread, 0.8);
}

}  // namespace
}  // namespace packsim
