// Parallel groups in the full loop: current split by resistance, group current
// conserved; a power load draws exactly P; spread draws are seeded and have the
// configured statistics.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>

#include "core/sim/plant.hpp"
#include "core/sim/simulation.hpp"
#include "test_support.hpp"
#include "tests/bits_of.hpp"

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


using test::bitsOf;

// The plant evaluates each cell's curves once, from its flattened copy of them with
// remembered table segments (models/cell/flat_cell.hpp), and keeps the reversible heat
// for the chemical-energy quadrature. Against the ECM's own functions at the same state,
// bit for bit: OCV, R0, the current split, each cell's heat and the quadratures, over a
// random walk of states (SOC inside and beyond 0…1, RC and hysteresis voltages,
// temperatures) on both current signs, for an Arrhenius table R0 with a charge R0,
// hysteresis and entropic heat (lipo), a discharged-Ah polynomial R0 (NCR18650) and a 2-D
// R0 table (LTO), in parallel groups with spread cells; a warm and a fresh set of signals
// agree too.
TEST(PackTopology, PlantSignalsAreTheEcmFunctionsBitForBit) {
  const std::vector<std::string> cells = {
      "{preset: lipo_5Ah, r0_charge_ohm: {x: [0.0, 1.0], y: [0.012, 0.009]}, "
      "hysteresis: {max_V: 0.03, rate_per_Ah: 20, instantaneous_V: 0.005}}",
      "{preset: ncr18650_3p1Ah}", "{preset: lto_20Ah}"};
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (const std::string& cell : cells) {
    const Scenario s = test::scenarioFromYaml(
        "name: flat\nseed: 5\npack:\n  series: 2\n  parallel: 3\n  initial_soc: 0.8\n  cell: " + cell +
        "\n  spread: {capacity_rel_sd: 0.02, r0_rel_sd: 0.05}\nload: {current_A: 3}\nrun: {duration_s: 10}\n");
    const Plant plant(s);
    const Pack& pk = plant.pack();
    const int n = pk.cellCount(), stride = plant.stride();
    std::vector<double> x(static_cast<size_t>(plant.stateSize()));
    plant.initialState(x.data());
    PlantSignals warm = plant.makeSignals();
    PlantInputs in;
    in.relay_closed = true;
    std::vector<double> dq(kQuadCount), dqFresh(kQuadCount);
    for (int step = 0; step < 600; ++step) {
      for (int c = 0; c < n; ++c) {
        double* xc = x.data() + c * stride;
        xc[0] = u(rng) < 0.03 ? -0.1 + 1.2 * u(rng) : xc[0] - 0.003 * u(rng);
        if (xc[0] < -0.1) xc[0] = 1.05;
        for (int k = 1; k < pk.layout.size(); ++k) xc[k] = 0.02 * (u(rng) - 0.5);
        x[static_cast<size_t>(plant.tempIndex(c))] = -20.0 + 80.0 * u(rng);
      }
      in.load.i0_A = -8.0 + 24.0 * u(rng);
      plant.evaluate(0.0, x.data(), in, warm);
      plant.quadratures(warm, dq.data());
      PlantSignals fresh = plant.makeSignals();
      plant.evaluate(0.0, x.data(), in, fresh);
      plant.quadratures(fresh, dqFresh.data());
      const double iPack = warm.pack_current_A;
      double chem = 0.0;
      for (int c = 0; c < n; ++c) {
        const size_t ci = static_cast<size_t>(c);
        const CellParams& p = pk.cells[ci];
        const double* xc = x.data() + c * stride;
        const double t_C = pk.cellTemp_C(c, xc);
        const double ocv = ecm::ocv(p, xc[0], t_C), r0 = ecm::r0(p, xc[0], t_C, iPack);
        ASSERT_EQ(bitsOf(warm.cell_ocv_V[ci]), bitsOf(ocv)) << cell << " cell " << c;
        ASSERT_EQ(bitsOf(warm.cell_r0_ohm[ci]), bitsOf(r0)) << cell << " cell " << c;
        const double emf = ecm::emf(p, xc, ocv) + ecm::instantHysteresis_V(p, iPack);
        const double v_g = warm.group_voltage_V[ci / 3];
        ASSERT_EQ(bitsOf(warm.cell_current_A[ci]), bitsOf((emf - v_g) / r0)) << cell << " cell " << c;
        const double i = warm.cell_current_A[ci];
        ASSERT_EQ(bitsOf(warm.heat_W[ci]), bitsOf(ecm::heatWithR0_W(p, xc, i, r0, t_C))) << cell << " cell " << c;
        chem += ocv * (i + warm.internal_A[ci]);
        if (p.has_entropic) chem += ecm::reversibleHeat_W(p, xc[0], i, t_C);
      }
      ASSERT_EQ(bitsOf(dq[kQuadChemEnergy_J]), bitsOf(chem)) << cell;
      for (int q = 0; q < kQuadCount; ++q) ASSERT_EQ(bitsOf(dq[static_cast<size_t>(q)]), bitsOf(dqFresh[static_cast<size_t>(q)]));
      for (int c = 0; c < n; ++c)
        ASSERT_EQ(bitsOf(warm.cell_current_A[static_cast<size_t>(c)]), bitsOf(fresh.cell_current_A[static_cast<size_t>(c)]));
    }
  }
}

// Plant::sample is evaluate without the heat: every other field to the bit, on packs with
// one and three cells a group, table and polynomial R0 with Arrhenius factors, passive
// balancing with a board node, the active balancer, a power load; the sample's signals
// warm (kept from call to call, as the loop keeps them), the evaluation's fresh.
TEST(PackTopology, SampleIsEvaluateWithoutTheHeatBitForBit) {
  const auto same = [](const std::vector<double>& a, const std::vector<double>& b) {
    if (a.size() != b.size()) return false;
    for (size_t i = 0; i < a.size(); ++i)
      if (bitsOf(a[i]) != bitsOf(b[i])) return false;
    return true;
  };
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (const char* file : {"eco_marathon_12s.yaml", "bench_6s_ncr18650_2C.yaml", "balance/solar_4s3p_active.yaml",
                           "balance/bench_6s_balancing.yaml"}) {
    const Scenario s = loadScenarioFile(test::scenarioDir() + "/" + file);
    const Plant plant(s);
    const Pack& pk = plant.pack();
    std::vector<double> x(static_cast<size_t>(plant.stateSize()));
    plant.initialState(x.data());
    PlantSignals warm = plant.makeSignals();
    PlantInputs in;
    in.relay_closed = true;
    in.load = s.load.segmentAt(0.0);
    for (int step = 0; step < 300; ++step) {
      for (int c = 0; c < pk.cellCount(); ++c) {
        double* xc = x.data() + c * plant.stride();
        xc[0] = 0.05 + 0.9 * u(rng);
        for (int k = 1; k < pk.layout.size(); ++k) xc[k] = 0.02 * (u(rng) - 0.5);
      }
      for (int j = 0; j < plant.thermal().nodeCount(); ++j) x[static_cast<size_t>(plant.tempIndex(j))] = -10.0 + 60.0 * u(rng);
      if (plant.busIndex() >= 0) x[static_cast<size_t>(plant.busIndex())] = 20.0 * u(rng);
      in.load.i0_A = -5.0 + 20.0 * u(rng);
      in.balancing.assign(static_cast<size_t>(pk.series), 0);
      in.converter_A.assign(static_cast<size_t>(pk.series), 0.0);
      for (int g = 0; g < pk.series; ++g) {
        in.balancing[static_cast<size_t>(g)] = u(rng) < 0.5;
        if (plant.busIndex() >= 0 && u(rng) < 0.5) in.converter_A[static_cast<size_t>(g)] = 2.0 * (u(rng) - 0.5);
      }
      in.bus_precharge = plant.busIndex() >= 0 && u(rng) < 0.3;
      in.discharge_fet_on = in.charge_fet_on = u(rng) < 0.8;
      PlantSignals full = plant.makeSignals();
      plant.evaluate(0.0, x.data(), in, full);
      plant.sample(0.0, x.data(), in, warm);
      ASSERT_TRUE(same(warm.cell_current_A, full.cell_current_A)) << file;
      ASSERT_TRUE(same(warm.cell_voltage_V, full.cell_voltage_V)) << file;
      ASSERT_TRUE(same(warm.group_voltage_V, full.group_voltage_V)) << file;
      ASSERT_TRUE(same(warm.node_temp_C, full.node_temp_C)) << file;
      ASSERT_TRUE(same(warm.cell_ocv_V, full.cell_ocv_V)) << file;
      ASSERT_TRUE(same(warm.cell_r0_ohm, full.cell_r0_ohm)) << file;
      ASSERT_TRUE(same(warm.cell_emf_V, full.cell_emf_V)) << file;
      ASSERT_TRUE(same(warm.balance_current_A, full.balance_current_A)) << file;
      const std::vector<double> scalars = {warm.pack_current_A, warm.pack_voltage_V, warm.ambient_C,
                                           warm.balance_heat_W, warm.charger_A, warm.bus_V, warm.bus_current_A,
                                           warm.converter_loss_W, warm.converter_from_modules_W,
                                           warm.converter_to_modules_W};
      const std::vector<double> fullScalars = {full.pack_current_A, full.pack_voltage_V, full.ambient_C,
                                               full.balance_heat_W, full.charger_A, full.bus_V, full.bus_current_A,
                                               full.converter_loss_W, full.converter_from_modules_W,
                                               full.converter_to_modules_W};
      ASSERT_TRUE(same(scalars, fullScalars)) << file << " step " << step;
    }
  }
}

}  // namespace
}  // namespace packsim
