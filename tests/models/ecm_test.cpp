#include "models/cell/ecm.hpp"
#include "models/cell/flat_cell.hpp"
#include "tests/bits_of.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <random>
#include <vector>

namespace packsim {
namespace {

CellParams cell() {
  CellParams p;
  p.capacity_Ah = 2.0;
  p.ocv_V = Curve::polynomial({0.8, 3.4});  // 3.4 + 0.8·soc
  p.r0_ohm = Curve::constant(0.02);
  p.rc = {{0.01, 1000.0}};
  p.coulombic_efficiency = 0.98;
  return p;
}

TEST(Ecm, DerivativesFollowTheEquations) {
  const CellParams p = cell();
  const double x[2] = {0.5, 0.004};
  double dx[2];
  ecm::derivatives(p, x, 3.0, dx);
  EXPECT_DOUBLE_EQ(dx[0], -3.0 / (3600.0 * 2.0));
  EXPECT_DOUBLE_EQ(dx[1], 3.0 / 1000.0 - 0.004 / 10.0);
  ecm::derivatives(p, x, -3.0, dx);  // charging: coulombic efficiency applies
  EXPECT_DOUBLE_EQ(dx[0], 0.98 * 3.0 / (3600.0 * 2.0));
}

TEST(Ecm, TerminalVoltageAndHeat) {
  const CellParams p = cell();
  const double x[2] = {0.5, 0.004};
  EXPECT_DOUBLE_EQ(ecm::terminalVoltage(p, x, 3.0), 3.8 - 0.004 - 3.0 * 0.02);
  EXPECT_DOUBLE_EQ(ecm::heat_W(p, x, 3.0), 9.0 * 0.02 + 0.004 * 0.004 / 0.01);
}


using test::bitsOf;

// FlatCell's OCV, R0 and reversible heat are ecm::ocv, ecm::r0 and ecm::reversibleHeat_W
// to the bit, with the hints carried from call to call: SOC inside, at and beyond 0…1
// (the OCV's extrapolation), both current signs (the charge R0), a discharged-Ah axis on
// a nominal capacity other than the cell's, an Arrhenius R0 and a 2-D OCV table.
TEST(Ecm, FlatCellIsTheEcmFunctionsBitForBit) {
  CellParams a = cell();
  a.ocv_V = Curve::table({0.0, 0.1, 0.3, 0.6, 0.9, 1.0}, {3.0, 3.4, 3.6, 3.8, 4.05, 4.2});
  a.r0_ohm = Curve::table({0.0, 0.2, 1.0}, {0.03, 0.02, 0.018}).withArrhenius(2000.0, 25.0);
  a.has_r0_charge = true;
  a.r0_charge_ohm = Curve::polynomial({0.01, 0.025}).withArrhenius(1500.0, 20.0);
  a.r0_scale = 1.07;
  a.has_entropic = true;
  a.docv_dT_V_per_K = Curve::table({0.0, 0.5, 1.0}, {-4e-4, 0.0, 5e-5});
  CellParams b = cell();
  b.capacity_Ah = 2.9;
  b.axis_capacity_Ah = 3.1;
  b.ocv_V = Curve::table2d({-0.05, 0.0, 1.0, 2.0, 3.1}, {0.0, 25.0, 40.0},
                           {{4.2, 4.15, 3.8, 3.5, 2.6}, {4.21, 4.16, 3.82, 3.55, 2.7}, {4.22, 4.17, 3.83, 3.57, 2.75}},
                           CurveAxis::Discharged_Ah);
  b.r0_ohm = Curve::polynomial({0.0292, -0.1914, 0.4481, -0.457, 0.1991, 0.0545}, CurveAxis::Discharged_Ah)
                 .withArrhenius(2250.0, 25.0);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (const CellParams& p : {a, b, cell()}) {
    const FlatCell f = FlatCell::of(p);
    CellHints h;
    double soc = 0.9;
    for (int n = 0; n < 4000; ++n) {
      soc = u(rng) < 0.05 ? -0.2 + 1.4 * u(rng) : soc - 0.002 * u(rng);
      if (soc < -0.2) soc = 1.1;
      const double t_C = -20.0 + 80.0 * u(rng), i_A = -5.0 + 15.0 * u(rng);
      ASSERT_EQ(bitsOf(f.ocv_V(p, soc, t_C, h)), bitsOf(ecm::ocv(p, soc, t_C))) << soc << " " << t_C;
      ASSERT_EQ(bitsOf(f.r0_ohm(soc, t_C, i_A, h)), bitsOf(ecm::r0(p, soc, t_C, i_A))) << soc << " " << i_A;
      ASSERT_EQ(bitsOf(f.reversibleHeat_W(soc, i_A, t_C, h)), bitsOf(ecm::reversibleHeat_W(p, soc, i_A, t_C)));
    }
  }
}

// FlatCell's EMF, heat and temperature are ecm::emf + ecm::instantHysteresis_V,
// ecm::heatWithParts_W and Pack::cellTemp_C's rule to the bit: constant RC pairs (read
// from the flat copy), a variable pair and more pairs than kFlatRc (read from the
// CellParams), hysteresis with an instantaneous step at both current signs and at rest,
// reversible heat, a cell whose curves read no temperature; and its derivatives
// (ecm::derivatives), inline for the first cell's constant pair.
TEST(Ecm, FlatCellEmfHeatAndTemperatureAreTheEcmFunctionsBitForBit) {
  CellParams a = cell();  // one constant pair, no temperature
  a.capacity_Ah = 3.07;
  a.coulombic_efficiency = 0.985;
  a.self_discharge_A = 2e-4;
  CellParams b = cell();
  b.rc = {{0.01, 1000.0}, {0.004, 20000.0}};
  b.has_hysteresis = true;
  b.hysteresis_max_V = Curve::constant(0.03);
  b.hysteresis_rate_per_Ah = 40.0;
  b.hysteresis_instant_V = 0.004;
  b.has_entropic = true;
  b.docv_dT_V_per_K = Curve::table({0.0, 0.5, 1.0}, {-4e-4, 0.0, 5e-5});
  CellParams c = cell();  // a variable pair: R over SOC and temperature
  RcPair var;
  var.variable = true;
  var.by_tau = true;
  var.r_curve = Curve::table({0.0, 0.5, 1.0}, {0.02, 0.01, 0.012}).withArrhenius(1800.0, 25.0);
  var.tau_curve = Curve::constant(30.0);
  c.rc = {{0.01, 1000.0}, var};
  CellParams d = cell();  // more pairs than the flat copy keeps
  for (int k = 0; k < FlatCell::kFlatRc; ++k) d.rc.push_back({0.002 * (k + 1), 500.0 * (k + 1)});
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const CellParams* cells[] = {&a, &b, &c, &d};
  const bool rcFlat[] = {true, true, false, false};  // the pairs' resistances read from the flat copy
  for (int k = 0; k < 4; ++k) {
    const CellParams& p = *cells[k];
    const FlatCell f = FlatCell::of(p);
    EXPECT_EQ(f.rc_constant, rcFlat[k]);
    const int slot = 1 + static_cast<int>(p.rc.size()) + (p.has_hysteresis ? 1 : 0);
    std::vector<double> x(static_cast<size_t>(slot) + 1);
    CellHints h;
    for (int n = 0; n < 2000; ++n) {
      x[0] = u(rng);
      for (int k = 1; k < slot; ++k) x[static_cast<size_t>(k)] = -0.05 + 0.1 * u(rng);
      x[static_cast<size_t>(slot)] = -20.0 + 80.0 * u(rng);
      const double r = u(rng), i_A = r < 0.1 ? 0.0 : r < 0.2 ? -0.0 : -5.0 + 15.0 * u(rng);
      const double t_C = f.temp_C(x.data(), slot);
      EXPECT_EQ(bitsOf(t_C), bitsOf(p.usesTemperature() ? x[static_cast<size_t>(slot)] : kReferenceTemp_C));
      const double ocv = ecm::ocv(p, x[0], t_C), r0 = ecm::r0(p, x[0], t_C, i_A);
      ASSERT_EQ(bitsOf(f.emf_V(x.data(), ocv, i_A)), bitsOf(ecm::emf(p, x.data(), ocv) + ecm::instantHysteresis_V(p, i_A)));
      const double rev = ecm::reversibleHeat_W(p, x[0], i_A, t_C);
      ASSERT_EQ(bitsOf(f.heat_W(p, x.data(), i_A, r0, rev, t_C)), bitsOf(ecm::heatWithParts_W(p, x.data(), i_A, r0, rev, t_C)));
      ASSERT_EQ(bitsOf(f.reversibleHeat_W(x[0], i_A, t_C, h)), bitsOf(rev));
      const double internal_A = n % 3 == 0 ? 0.0 : 0.01 * u(rng);
      std::vector<double> dxFlat(x.size(), -1.0), dxEcm(x.size(), -1.0);
      f.derivatives(p, x.data(), i_A, dxFlat.data(), internal_A, t_C);
      ecm::derivatives(p, x.data(), i_A, dxEcm.data(), internal_A, t_C);
      for (size_t j = 0; j < x.size(); ++j) ASSERT_EQ(bitsOf(dxFlat[j]), bitsOf(dxEcm[j])) << j;
    }
  }
}

}  // namespace
}  // namespace packsim
