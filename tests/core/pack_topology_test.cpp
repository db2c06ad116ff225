// Parallel groups in the full loop: current split by resistance, group current
// conserved; a power load draws exactly P; spread draws are seeded and have the
// configured statistics.
#include <gtest/gtest.h>

#include <cmath>

#include "core/sim/plant.hpp"
#include "core/sim/simulation.hpp"
#include "test_support.hpp"

namespace packsim {
namespace {

std::string parallelPack(const std::string& extra) {
  return "name: par\nseed: 2\n"
         "pack:\n  series: 2\n  parallel: 3\n  initial_soc: 0.8\n"
         "  cell: {capacity_Ah: 2.0, ocv_V: {poly: [0.8, 3.4]}, r0_ohm: 0.03}\n" + extra +
         "hardware:\n  cell_adc: {noise_mV_rms: 0}\n  current_sense: {shunt_ohm: 0.001, amp_gain: 20, noise_A_rms: 0}\n"
         "load: {current_A: 9}\nrun: {duration_s: 600, rtol: 1e-9}\noutput: {interval_s: 0.01}\n";
}

TEST(PackTopology, DoubleResistanceCellCarriesItsShareAndGroupCurrentIsConserved) {
  const Scenario s = test::scenarioFromYaml(parallelPack("  cells: [{cell: 2, r0_scale: 2.0}]\n"));
  const RunResult r = runScenario(s);
  const Recording& rec = r.rec;
  // At the first sample with current every cell still has (almost) the same SOC: the
  // split is by conductance alone, 1/R : 1/(2R) : 1/R = 2/5 : 1/5 : 2/5 of 9 A. Within
  // one 10 ms sample the SOCs drift apart by < 1.8 A * 0.01 s / 7200 As = 2.5e-6, which
  // shifts the split by < 0.8 V * 2.5e-6 / 0.03 ohm ~ 7e-5 A.
  size_t first = 0;
  while (first < rec.samples() && rec.pack_current_A[first] == 0.0) ++first;
  ASSERT_LT(first, rec.samples());
  const size_t k = first * 6;
  EXPECT_NEAR(rec.cell_current_A[k + 0], 3.6, 1e-4);
  EXPECT_NEAR(rec.cell_current_A[k + 1], 1.8, 1e-4);
  EXPECT_NEAR(rec.cell_current_A[k + 2], 3.6, 1e-4);
  // Equal cells of group 2 share equally.
  EXPECT_NEAR(rec.cell_current_A[k + 3], 3.0, 1e-9);
  // Conservation in every sample: Σ cell currents of a group = pack current.
  for (size_t i = 0; i < rec.samples(); ++i)
    for (int g = 0; g < 2; ++g) {
      double sum = 0.0;
      for (int p = 0; p < 3; ++p) sum += rec.cell_current_A[i * 6 + static_cast<size_t>(g * 3 + p)];
      ASSERT_NEAR(sum, rec.pack_current_A[i], 1e-12 * 9.0 + 1e-13) << "sample " << i;
    }
}

TEST(PackTopology, PowerLoadDrawsExactlyItsPower) {
  std::string y = parallelPack("");
  y.replace(y.find("load: {current_A: 9}"), 20, "load: {power_W: 60}");
  const RunResult r = runScenario(test::scenarioFromYaml(y));
  int checked = 0;
  for (size_t i = 0; i < r.rec.samples(); ++i) {
    if (r.rec.pack_current_A[i] == 0.0) continue;
    ASSERT_NEAR(r.rec.pack_voltage_V[i] * r.rec.pack_current_A[i], 60.0, 1e-9) << "t=" << r.rec.time_s[i];
    ++checked;
  }
  EXPECT_GT(checked, 50000);
  // As the pack voltage sags the current must rise to hold the power.
  EXPECT_GT(r.rec.pack_current_A.back(), r.rec.pack_current_A[test::sampleAt(r.rec, 1.0)]);
}

TEST(PackTopology, SpreadHasConfiguredStatisticsAndIsSeeded) {
  const std::string y = "name: spread\nseed: 9\npack:\n  series: 200\n  parallel: 5\n"
                        "  cell: {capacity_Ah: 3.0, ocv_V: 3.7, r0_ohm: 0.02}\n"
                        "  spread: {capacity_rel_sd: 0.02, r0_rel_sd: 0.05, initial_soc_sd: 0.01}\n"
                        "load: {current_A: 1}\nrun: {duration_s: 1}\n";
  const Scenario s = test::scenarioFromYaml(y);
  const Plant a(s), b(s);
  const int n = a.pack().cellCount();
  double m = 0, m2 = 0, r = 0, r2 = 0;
  for (int c = 0; c < n; ++c) {
    const CellParams& p = a.pack().cells[static_cast<size_t>(c)];
    EXPECT_EQ(p.capacity_Ah, b.pack().cells[static_cast<size_t>(c)].capacity_Ah);  // same seed, same draw
    m += p.capacity_Ah;
    m2 += p.capacity_Ah * p.capacity_Ah;
    r += p.r0_scale;
    r2 += p.r0_scale * p.r0_scale;
  }
  m /= n;
  r /= n;
  // 1000 draws: the sample mean is within 4 standard errors, the sd within 10 %.
  EXPECT_NEAR(m, 3.0, 4 * 0.06 / std::sqrt(n));
  EXPECT_NEAR(std::sqrt(m2 / n - m * m), 0.06, 0.006);
  EXPECT_NEAR(r, 1.0, 4 * 0.05 / std::sqrt(n));
  EXPECT_NEAR(std::sqrt(r2 / n - r * r), 0.05, 0.005);
  Scenario other = s;
  other.run.seed = 10;
  EXPECT_NE(Plant(other).pack().cells[0].capacity_Ah, a.pack().cells[0].capacity_Ah);
}

TEST(PackTopology, GroupLevelSpreadIsSharedWithinAGroup) {
  const std::string y = "name: spread\nseed: 9\npack:\n  series: 4\n  parallel: 3\n"
                        "  cell: {capacity_Ah: 3.0, ocv_V: 3.7, r0_ohm: 0.02}\n"
                        "  spread: {level: group, capacity_rel_sd: 0.05}\n"
                        "load: {current_A: 1}\nrun: {duration_s: 1}\n";
  const Plant p(test::scenarioFromYaml(y));
  for (int g = 0; g < 4; ++g)
    for (int k = 1; k < 3; ++k)
      EXPECT_EQ(p.pack().cells[static_cast<size_t>(g * 3 + k)].capacity_Ah, p.pack().cells[static_cast<size_t>(g * 3)].capacity_Ah);
  EXPECT_NE(p.pack().cells[0].capacity_Ah, p.pack().cells[3].capacity_Ah);
}

}  // namespace
}  // namespace packsim
