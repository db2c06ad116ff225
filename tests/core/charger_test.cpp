// CC-CV charger (models/hw/charger) on the reference system C cell: constant current at
// 885 mA until the terminal reaches 4.2 V, then constant voltage with a falling current,
// ending at the taper end current; a charge-side fault stops it.
#include <gtest/gtest.h>

#include <cmath>

#include "core/sim/simulation.hpp"
#include "test_support.hpp"

namespace packsim {
namespace {

std::string chargerYaml(const std::string& extra = "") {
  return "name: cccv\nseed: 2\n"
         "pack: {series: 1, initial_soc: 0.3, cell: {preset: ncr18650_3p1Ah}}\n"
         "hardware:\n"
         "  cell_adc: {lsb_uV: 100, bits: 16, noise_mV_rms: 0}\n"
         "  thermistors: {at_groups: [1]}\n"
         "  current_sense: {shunt_ohm: 0.001, amp_gain: 10, noise_A_rms: 0}\n"
         "bms: {tick_ms: 1000}\n"
         "load: {charger: {current_A: 0.885, voltage_V: 4.2, end_current_A: 0.1}}\n"
         "run: {duration_s: 36000}\n"
         "output: {interval_s: 1}\n" + extra;
}

TEST(Charger, SystemCCellChargesCcThenCvAndEndsAtTheEndCurrent) {
  const RunResult r = runScenario(test::scenarioFromYaml(chargerYaml()));
  const Recording& rec = r.rec;
  const double cv = test::eventTime(r, "charger", "constant voltage");
  const double done = test::eventTime(r, "charger", "done");
  ASSERT_GT(cv, 0.0);
  ASSERT_GT(done, cv);
  EXPECT_NEAR(rec.time_s.back(), done, 1e-9) << "the run stops when the charge ends";
  double prev = INFINITY;
  for (size_t i = 0; i < rec.samples(); ++i) {
    const double t = rec.time_s[i], i_chg = rec.charger_current_A[i], v = rec.pack_voltage_V[i];
    EXPECT_NEAR(-rec.pack_current_A[i], i_chg, 1e-12);
    if (t > 3.0 && t < cv - 1.0) {  // CC: the limit, below the setpoint
      EXPECT_NEAR(i_chg, 0.885, 1e-9) << t;
      EXPECT_LT(v, 4.2 + 1e-9) << t;
    }
    if (t > cv && t < done) {  // CV: at the setpoint, the current only falls
      EXPECT_NEAR(v, 4.2, 1e-6) << t;
      EXPECT_LE(i_chg, prev + 1e-9) << t;
      EXPECT_GE(i_chg, 0.1 - 1e-9) << t;
    }
    if (t > cv) prev = i_chg;
  }
  // It ends at the end current: the last current is just below it (one tick of taper).
  const double last = rec.charger_current_A.back();
  EXPECT_LT(last, 0.1);
  EXPECT_GT(last, 0.095);
  // The charge put in equals what the cell's SOC gained (coulombic efficiency 0.995).
  const double gained_Ah = (rec.cell_soc.back() - rec.cell_soc.front()) * 3.1;
  EXPECT_NEAR(gained_Ah, -0.995 * r.quad[kQuadCharge_As] / 3600.0, 1e-3 * gained_Ah);
  EXPECT_GT(rec.cell_soc.back(), 0.95);
}

TEST(Charger, AChargeSideFaultStopsCharging) {
  // A 28 C over-temperature-charge limit in a 30 C room: the fault comes while charging.
  const std::string extra =
      "ambient: {temp_C: 30}\n";
  std::string yaml = chargerYaml(extra);
  yaml.replace(yaml.find("bms: {tick_ms: 1000}"), 20,
               "bms: {tick_ms: 1000, protections: {overtemperature_charge: {threshold_C: 28, delay_ms: 2000}}}");
  const RunResult r = runScenario(test::scenarioFromYaml(yaml));
  const double trip = test::eventTime(r, "fault_active", "overtemperature_charge");
  ASSERT_GT(trip, 0.0);
  const Recording& rec = r.rec;
  for (size_t i = 0; i < rec.samples(); ++i) {
    if (rec.time_s[i] >= trip) {
      EXPECT_EQ(rec.charger_enable[i], 0) << rec.time_s[i];
      EXPECT_EQ(rec.charger_request_mA[i], 0);
    }
    if (rec.time_s[i] >= trip + 1.0) EXPECT_EQ(rec.charger_current_A[i], 0.0) << rec.time_s[i];
  }
}

}  // namespace
}  // namespace packsim
