// Temperature-dependent cell elements against closed forms, through the whole loop and
// both integrators:
//
//   Arrhenius   R0(T) = R0_ref · exp(K·(1/T_K - 1/T_ref,K))     (cell held at T)
//   2-D table   R0(soc, T) bilinear between grid rows
//   charge R0   V = OCV - I·R0_charge - v1 for I < 0
//   entropic    T(∞) solves G·(T - T_amb) = I²·(R0 + R1) - I·(T + 273.15)·dOCV/dT
//   energy      ∫(OCV - T·dOCV/dT)·I dt = load + heat (Joule + reversible) + ½·C·v1²
#include <gtest/gtest.h>

#include <cmath>

#include "core/sim/cvode_integrator.hpp"
#include "core/sim/plant.hpp"
#include "core/sim/simulation.hpp"
#include "plant_only.hpp"
#include "test_support.hpp"

namespace packsim {
namespace {

constexpr double kQ = 2.0, kR1 = 0.01, kC1 = 1000.0, kSoc0 = 0.8;

double ocv(double soc) { return 3.4 + 0.8 * soc; }

// One cell whose temperature cannot move (huge heat capacity, no path to ambient):
// held at temp_C so a temperature-dependent element has one known value.
std::string heldCell(double temp_C, const std::string& r0Yaml, const std::string& extraCell = "") {
  const std::string t = std::to_string(temp_C);
  return "name: held\nseed: 3\npack:\n  series: 1\n  initial_soc: 0.8\n  initial_temp_C: " + t +
         "\n  cell:\n    capacity_Ah: 2.0\n    ocv_V: {poly: [0.8, 3.4]}\n    r0_ohm: " + r0Yaml +
         "\n    rc_pairs: [{r_ohm: 0.01, c_F: 1000}]\n    heat_capacity_J_per_K: 1.0e12\n    g_ambient_W_per_K: 0\n" +
         extraCell +
         "hardware:\n  cell_adc: {lsb_uV: 100, bits: 16, noise_mV_rms: 0}\n  thermistors: {at_groups: [1]}\n"
         "  current_sense: {shunt_ohm: 0.001, amp_gain: 20, noise_A_rms: 0}\n"
         "bms:\n  protections:\n    undertemperature: {threshold_C: -40}\n    undertemperature_charge: {threshold_C: -40}\n"
         "ambient: {temp_C: " + t + "}\n";
}

std::string runFor(const std::string& solver) {
  return "run: {duration_s: 300, " + std::string(solver == "fast" ? "solver: fast" : "rtol: 1e-9") + "}\n";
}

// Terminal voltage against V = OCV(soc) - I·R0 - v1 from the relay's closing on.
void expectClosedForm(const std::string& yaml, double i_A, double r0_ohm) {
  for (const char* solver : {"cvode", "fast"}) {
    const Scenario s = test::scenarioFromYaml(yaml + "load: {current_A: " + std::to_string(i_A) + "}\n" + runFor(solver));
    const RunResult r = runScenario(s);
    const double tc = test::eventTime(r, "relay", "close");
    ASSERT_GE(tc, 0.0) << solver;
    ASSERT_FALSE(r.summary.tripped) << solver;
    for (double t : {10.0, 100.0, 299.0}) {
      const size_t k = test::sampleAt(r.rec, t);
      const double tau = t - tc;
      const double v = ocv(kSoc0 - i_A * tau / (3600.0 * kQ)) - i_A * r0_ohm - i_A * kR1 * (1.0 - std::exp(-tau / (kR1 * kC1)));
      EXPECT_NEAR(r.rec.cell_voltage_V[k], v, 1e-6 * v) << solver << " t=" << t;
    }
  }
}

TEST(CellTemperature, ArrheniusR0AtAColdCell) {
  // 0.02 Ω at 25 °C, K = 3000 K: at -15 °C the factor is exp(3000·(1/258.15 - 1/298.15)) = 4.75.
  const double r0 = 0.02 * std::exp(3000.0 * (1.0 / 258.15 - 1.0 / 298.15));
  ASSERT_NEAR(r0 / 0.02, 4.75, 0.01);
  expectClosedForm(heldCell(-15.0, "{poly: [0.02], arrhenius_K: 3000, ref_temp_C: 25}"), 3.0, r0);
}

TEST(CellTemperature, TwoDimensionalTableIsBilinear) {
  // Rows at -15 and 5 °C over SOC 0.5 / 1.0; the cell sits at -5 °C (halfway) and its
  // SOC moves within 0.8 → 0.675, so R0 = mean of the rows at that SOC: linear in SOC.
  const std::string table = "{x: [0.5, 1.0], temp_C: [-15, 5], y: [[0.08, 0.06], [0.02, 0.01]]}";
  for (const char* solver : {"cvode", "fast"}) {
    const Scenario s = test::scenarioFromYaml(heldCell(-5.0, table) + "load: {current_A: 3}\n" + runFor(solver));
    const RunResult r = runScenario(s);
    const double tc = test::eventTime(r, "relay", "close");
    for (double t : {10.0, 299.0}) {
      const size_t k = test::sampleAt(r.rec, t);
      const double tau = t - tc, soc = kSoc0 - 3.0 * tau / (3600.0 * kQ);
      const double w = (soc - 0.5) / 0.5;
      const double r0 = 0.5 * ((0.08 + w * (0.06 - 0.08)) + (0.02 + w * (0.01 - 0.02)));
      const double v = ocv(soc) - 3.0 * r0 - 3.0 * kR1 * (1.0 - std::exp(-tau / (kR1 * kC1)));
      EXPECT_NEAR(r.rec.cell_voltage_V[k], v, 1e-6 * v) << solver << " t=" << t;
    }
  }
}

// issue 28: overriding one field of a preset keeps the rest of it, the temperature law
// of that field included. `r0_ohm: 0.020` on the NCR18650 preset (Arrhenius, 2250 K at
// 25 C) is R0 at 25 C; before, it was a constant and 15/25/35 C gave the same heat.
std::string presetCellHeldAt(double temp_C, const std::string& r0Override) {
  const std::string t = std::to_string(temp_C);
  return "name: preset_override\nseed: 3\npack:\n  series: 1\n  initial_soc: 0.8\n  initial_temp_C: " + t +
         "\n  cell:\n    preset: ncr18650_3p1Ah\n    r0_ohm: " + r0Override +
         "\n    heat_capacity_J_per_K: 1.0e12\n    g_ambient_W_per_K: 0\n"
         "hardware:\n  cell_adc: {lsb_uV: 100, bits: 16, noise_mV_rms: 0}\n  thermistors: {at_groups: [1]}\n"
         "  current_sense: {shunt_ohm: 0.001, amp_gain: 20, noise_A_rms: 0}\n"
         "ambient: {temp_C: " + t + "}\nload: {current_A: 3}\nrun: {duration_s: 300, solver: fast}\n";
}

TEST(CellTemperature, PresetFieldOverrideKeepsThePresetsTemperatureLaw) {
  const Scenario s25 = test::scenarioFromYaml(presetCellHeldAt(25.0, "0.020"));
  const Curve& r0 = s25.pack.cell.r0_ohm;
  const double q = s25.pack.cell.axis_capacity_Ah;
  for (double soc : {0.2, 0.8}) {
    EXPECT_DOUBLE_EQ(r0.eval(soc, q, 25.0), 0.020);  // the new value, at the reference temperature
    EXPECT_NEAR(r0.eval(soc, q, 0.0), 0.020 * arrheniusFactor(2250.0, 0.0, 25.0), 1e-12);  // x2 at 0 C
  }
  EXPECT_NEAR(r0.eval(0.5, q, 0.0) / 0.020, 2.0, 0.05);
  // The rest of the preset stays: its RC pair, capacity and limits.
  ASSERT_EQ(s25.pack.cell.rc.size(), 1u);
  EXPECT_DOUBLE_EQ(s25.pack.cell.rc[0].r_ohm, 0.015);
  EXPECT_DOUBLE_EQ(s25.pack.cell.capacity_Ah, 3.1);

  // A cell held at 15 / 25 / 35 C under 3 A: colder, more heat; R0's share of the heat
  // differs from 25 C's by I^2 * t_closed * 0.020 * (factor(T) - 1) (the RC pair and the
  // OCV do not depend on temperature; the cell's temperature cannot move).
  double heat25 = 0.0, closed_s = 0.0;
  std::vector<double> heat;
  for (double t : {15.0, 25.0, 35.0}) {
    const RunResult r = runScenario(test::scenarioFromYaml(presetCellHeldAt(t, "0.020")));
    heat.push_back(r.summary.heat_Wh);
    if (t == 25.0) {
      heat25 = r.summary.heat_Wh;
      closed_s = r.summary.duration_s - test::eventTime(r, "relay", "close");
    }
  }
  EXPECT_GT(heat[0], heat[1] * 1.05);
  EXPECT_GT(heat[1], heat[2] * 1.05);
  for (const auto& [t, h] : {std::pair{15.0, heat[0]}, std::pair{35.0, heat[2]}}) {
    const double expected_Wh = 9.0 * closed_s * 0.020 * (arrheniusFactor(2250.0, t, 25.0) - 1.0) / 3600.0;
    EXPECT_NEAR(h - heat25, expected_Wh, 0.01 * std::abs(expected_Wh)) << t;
  }
}

TEST(CellTemperature, PresetOverrideWithItsOwnLawOrOnATableOverTemperature) {
  // An override that states its own law replaces the preset's whole.
  const Scenario own = test::scenarioFromYaml(presetCellHeldAt(25.0, "{poly: [0.02], arrhenius_K: 0, ref_temp_C: 25}"));
  EXPECT_FALSE(own.pack.cell.r0_ohm.dependsOnTemperature());
  // The LTO preset's R0 is a table over temp_C (x1.8 at 0 C, x4 at -15 C at SOC 1): a
  // single value is R0 at 25 C and keeps the table's ratios.
  std::string lto = test::simpleCellYaml();
  lto.replace(lto.find("    capacity_Ah: 2.0\n"), 21, "    preset: lto_20Ah\n");
  lto.replace(lto.find("    ocv_V: {poly: [0.8, 3.4]}\n"), 30, "");
  lto.replace(lto.find("    r0_ohm: 0.02\n"), 17, "    r0_ohm: 0.003\n");
  const Scenario s = test::scenarioFromYaml(lto + test::kSimpleLoadYaml);
  const Curve& r0 = s.pack.cell.r0_ohm;
  const double q = s.pack.cell.axis_capacity_Ah;
  EXPECT_NEAR(r0.eval(1.0, q, 25.0), 0.003, 1e-15);
  EXPECT_NEAR(r0.eval(0.5, q, 25.0), 0.003, 1e-15);
  EXPECT_NEAR(r0.eval(1.0, q, 0.0), 0.003 * 0.0027 / 0.0015, 1e-12);
  EXPECT_NEAR(r0.eval(1.0, q, -15.0), 0.003 * 0.0060 / 0.0015, 1e-12);
  // A curve over SOC alone cannot carry the table's rows: one error saying what to write.
  std::string curve = lto;
  curve.replace(curve.find("    r0_ohm: 0.003\n"), 18, "    r0_ohm: {x: [0, 1], y: [0.004, 0.003]}\n");
  const std::string e = test::yamlErrorOf(curve + test::kSimpleLoadYaml);
  EXPECT_NE(e.find("pack.cell.r0_ohm: the preset's curve is a table over temp_C"), std::string::npos) << e;
}

TEST(CellTemperature, ChargeR0AppliesWhenCharging) {
  const std::string yaml = heldCell(25.0, "0.02", "    r0_charge_ohm: 0.05\n");
  expectClosedForm(yaml, -1.0, 0.05);  // charging: the charge R0
  expectClosedForm(yaml, 1.0, 0.02);   // discharging: r0_ohm
}

TEST(CellTemperature, ReversibleHeatShiftsTheSteadyTemperature) {
  // dOCV/dT = +0.5 mV/K: discharge absorbs I·T·dOCV/dT (≈ 0.45 W at 3 A), more than
  // the Joule heat 0.27 W, so the cell settles *below* ambient.
  constexpr double kI = 3.0, kD = 5e-4, kG = 0.1, kTa = 25.0;
  const Scenario s = test::scenarioFromYaml(test::simpleCellYaml() + "load: {current_A: 3}\nrun: {duration_s: 4800}\n");
  Scenario e = s;
  e.pack.cell.has_entropic = true;
  e.pack.cell.docv_dT_V_per_K = Curve::constant(kD);
  const Plant plant(e);
  test::PlantOnly ode(plant, kI);
  CvodeIntegrator integ(ode, 1e-10);
  std::vector<double> x(static_cast<size_t>(plant.stateSize()));
  plant.initialState(x.data());
  integ.reset(0.0, x.data());
  integ.advance(4800.0, 1e9);  // 12 thermal time constants (C/G = 400 s)
  const double tss = (kTa + (kI * kI * (0.02 + kR1) - kI * 273.15 * kD) / kG) / (1.0 + kI * kD / kG);
  ASSERT_LT(tss, kTa);
  EXPECT_NEAR(integ.state()[plant.tempIndex(0)], tss, 1e-4);
}

// Race profile with charge and discharge, an Arrhenius R0, a charge R0 and dOCV/dT:
// the enthalpy balance holds, and the reversible part of the heat is -∫I·T_K·dOCV/dT.
TEST(CellTemperature, EnergyBalanceIncludesReversibleHeat) {
  const std::string cell = test::simpleCellYaml(3);
  auto withCurves = [&](bool entropic) {
    std::string y = cell;
    const std::string r0 = "    r0_ohm: 0.02\n";
    y.replace(y.find(r0), r0.size(),
              "    r0_ohm: {poly: [0.02], arrhenius_K: 2500, ref_temp_C: 25}\n    r0_charge_ohm: 0.03\n" +
                  std::string(entropic ? "    docv_dT_V_per_K: {x: [0, 1], y: [-0.0008, -0.0002]}\n" : ""));
    return test::scenarioFromYaml(y +
                                  "load:\n  segments:\n    - {duration_s: 40, current_A: 8}\n"
                                  "    - {duration_s: 30, current_A: -2}\n    - {duration_s: 20, current_A: 0}\n"
                                  "  laps: 8\nrun: {rtol: 1e-8}\noutput: {interval_s: 0.05}\n");
  };
  for (bool entropic : {true, false}) {
    const RunResult r = runScenario(withCurves(entropic));
    ASSERT_FALSE(r.summary.tripped);
    const size_t last = r.rec.samples() - 1;
    ASSERT_EQ(r.rec.pack_current_A[last], 0.0);  // at rest: v1 = OCV - V
    double stored = 0.0, reversible = 0.0;
    for (int c = 0; c < r.rec.cells; ++c) {
      const size_t k = last * static_cast<size_t>(r.rec.cells) + static_cast<size_t>(c);
      const double v1 = ocv(r.rec.cell_soc[k]) - r.rec.cell_voltage_V[k];
      stored += 0.5 * kC1 * v1 * v1;
    }
    const double chem = r.quad[kQuadChemEnergy_J];
    EXPECT_NEAR(chem, r.quad[kQuadLoadEnergy_J] + r.quad[kQuadHeat_J] + stored, 1e-5 * chem) << entropic;
    // Reversible heat from the recorded samples (trapezoid), against chem - ∫OCV·I.
    double ocvEnergy = 0.0;
    for (size_t i = 1; i < r.rec.samples(); ++i) {
      const double h = r.rec.time_s[i] - r.rec.time_s[i - 1];
      for (int c = 0; c < r.rec.cells; ++c) {
        auto at = [&](size_t j, bool rev) {
          const size_t k = j * static_cast<size_t>(r.rec.cells) + static_cast<size_t>(c);
          const double soc = r.rec.cell_soc[k], cur = r.rec.cell_current_A[k];
          if (!rev) return ocv(soc) * cur;
          return entropic ? -cur * (r.rec.cell_temp_C[k] + 273.15) * (-0.0008 + 0.0006 * soc) : 0.0;
        };
        reversible += 0.5 * h * (at(i - 1, true) + at(i, true));
        ocvEnergy += 0.5 * h * (at(i - 1, false) + at(i, false));
      }
    }
    if (entropic) EXPECT_GT(std::fabs(reversible), 100.0);
    EXPECT_NEAR(chem - ocvEnergy, reversible, 2e-3 * std::fabs(chem) + 1.0) << entropic;
  }
}

}  // namespace
}  // namespace packsim
