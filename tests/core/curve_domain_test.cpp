// Every cell curve and table is checked over its whole domain at load time (issue 16):
// an error names file:line:column of the curve, the field, and the SOC (and
// temperature) where it fails.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "test_support.hpp"

namespace packsim {
namespace {

namespace fs = std::filesystem;

std::string errorOf(const std::string& yaml) { return test::yamlErrorOf(yaml); }

const std::string& kLoad = test::kSimpleLoadYaml;

// The simple cell with one line of its cell block replaced (`key: ...` on line `line`).
std::string cellWith(const std::string& key, const std::string& value) {
  std::string y = test::simpleCellYaml() + kLoad;
  const size_t at = y.find("    " + key + ":");
  const size_t end = y.find('\n', at);
  y.replace(at, end - at, "    " + key + ": " + value);
  return y;
}

bool has(const std::string& e, const std::string& part) { return e.find(part) != std::string::npos; }

TEST(CurveDomain, R0PolynomialNegativeBelowHalfSoc) {
  // 0.04·soc - 0.02: negative from SOC 0 up to 0.5.
  const std::string e = errorOf(cellWith("r0_ohm", "{poly: [0.04, -0.02]}"));
  EXPECT_TRUE(has(e, "test.yaml:10:")) << e;
  EXPECT_TRUE(has(e, "pack.cell.r0_ohm: must be > 0 over SOC 0..1 but is -0.02 at SOC 0 (and up to SOC 0.5)")) << e;
}

TEST(CurveDomain, OcvFallingAsSocRises) {
  const std::string e = errorOf(cellWith("ocv_V", "{x: [0, 0.5, 1], y: [3.0, 3.8, 3.6]}"));
  EXPECT_TRUE(has(e, "test.yaml:9:")) << e;
  EXPECT_TRUE(has(e, "pack.cell.ocv_V: must rise strictly with SOC but falls from 3.8 V at SOC 0.5")) << e;
}

TEST(CurveDomain, OcvFlatInsideTheTable) {
  const std::string e = errorOf(cellWith("ocv_V", "{x: [0, 0.5, 1], y: [3.0, 3.7, 3.7]}"));
  EXPECT_TRUE(has(e, "must rise strictly with SOC but stays flat from 3.7 V at SOC 0.5")) << e;
  // A plain number is an ideal constant source, accepted (test rigs, what-ifs).
  EXPECT_EQ(errorOf(cellWith("ocv_V", "3.7")), "<no error>");
}

TEST(CurveDomain, OcvHeldFlatBeyondItsTableIsAccepted) {
  // The table covers SOC 0.1..0.9; held flat outside (documented), rising inside.
  EXPECT_EQ(errorOf(cellWith("ocv_V", "{x: [0.1, 0.9], y: [3.4, 4.1]}")), "<no error>");
}

TEST(CurveDomain, TwoDimensionalOcvFallingAtOneTemperatureNamesIt) {
  const std::string e =
      errorOf(cellWith("ocv_V", "{x: [0, 0.5, 1], temp_C: [-10, 25], y: [[3.0, 3.9, 3.8], [3.0, 3.6, 4.1]]}"));
  EXPECT_TRUE(has(e, "test.yaml:9:")) << e;
  EXPECT_TRUE(has(e, "falls from 3.9 V at SOC 0.5 at -10 C")) << e;
}

TEST(CurveDomain, TwoDimensionalR0NegativeAtOneTemperature) {
  // A negative entry is refused where it is written, naming its row's temperature.
  const std::string e = errorOf(cellWith("r0_ohm", "{x: [0, 1], temp_C: [0, 40], y: [[0.03, 0.02], [0.01, -0.01]]}"));
  EXPECT_TRUE(has(e, "test.yaml:10:67: pack.cell.r0_ohm.y: row 2 (temp_C 40): value -0.01 is out of range; allowed (0, 10]")) << e;
  // A polynomial that turns negative at a cold temperature only through its Arrhenius
  // factor cannot (the factor is positive); a polynomial negative at SOC 1 is named there.
  const std::string p = errorOf(cellWith("r0_ohm", "{poly: [-0.04, 0.03], arrhenius_K: 3000, ref_temp_C: 25}"));
  EXPECT_TRUE(has(p, "must be > 0 over SOC 0..1 but is")) << p;
  EXPECT_TRUE(has(p, "at -40 C")) << p;
}

TEST(CurveDomain, RcTimeConstantNegative) {
  const std::string e = errorOf(cellWith("rc_pairs", "[{r_ohm: 0.01, tau_s: {poly: [100, -60]}}]"));
  EXPECT_TRUE(has(e, "test.yaml:11:")) << e;
  EXPECT_TRUE(has(e, "tau_s: must be > 0 over SOC 0..1 but is -60 at SOC 0 (and up to SOC 0.6)")) << e;
}

TEST(CurveDomain, RcResistanceTableNotPositive) {
  const std::string e = errorOf(cellWith("rc_pairs", "[{r_ohm: {x: [0, 1], y: [0.0, 0.01]}, c_F: 1000}]"));
  EXPECT_TRUE(has(e, "r_ohm")) << e;
}

TEST(CurveDomain, NonFiniteValue) {
  const std::string e = errorOf(cellWith("r0_ohm", "{poly: [1e308, 1e308, 1e308]}"));
  EXPECT_TRUE(has(e, "test.yaml:10:")) << e;
  EXPECT_TRUE(has(e, "r0_ohm.poly[0]: 1e308 is out of range; allowed [-1000000000, 1000000000]")) << e;
}

TEST(CurveDomain, ChargeR0Checked) {
  std::string y = test::simpleCellYaml() + kLoad;
  y.replace(y.find("    r0_ohm: 0.02\n"), 17, "    r0_ohm: 0.02\n    r0_charge_ohm: {poly: [0.01, -0.02]}\n");
  const std::string e = errorOf(y);
  EXPECT_TRUE(has(e, "test.yaml:11:")) << e;
  EXPECT_TRUE(has(e, "r0_charge_ohm: must be > 0")) << e;
}

TEST(CurveDomain, TableShapeErrors) {
  EXPECT_TRUE(has(errorOf(cellWith("r0_ohm", "{x: [0, 1], temp_C: [0, 25], y: [[0.02, 0.01]]}")),
                  "one row of y per temp_C value"));
  EXPECT_TRUE(has(errorOf(cellWith("r0_ohm", "{x: [0, 1], temp_C: [0, 25], y: [[0.02, 0.01], [0.02]]}")),
                  "row 2"));
  EXPECT_TRUE(has(errorOf(cellWith("r0_ohm", "{x: [0, 1], temp_C: [25, 0], y: [[0.02, 0.01], [0.02, 0.01]]}")),
                  "temp_C: values must increase strictly"));
  EXPECT_TRUE(has(errorOf(cellWith("r0_ohm", "{x: [0, 1], temp_C: [0, 25], y: [[0.02, 0.01], [0.02, 0.01]], "
                                             "arrhenius_K: 3000, ref_temp_C: 25}")),
                  "drop arrhenius_K"));
  EXPECT_TRUE(has(errorOf(cellWith("r0_ohm", "{poly: [0.02], arrhenius_K: 3000}")), "ref_temp_C"));
}

// A bad curve in a preset file names the preset file and its line.
TEST(CurveDomain, PresetCurveNamesThePresetFile) {
  const fs::path dir = test::processTempDir("packsim_curve_domain_test");
  fs::create_directories(dir / "cells");
  {
    std::ofstream(dir / "cells" / "bad_cell.yaml") << "capacity_Ah: 2.0\nocv_V: {poly: [0.8, 3.4]}\n"
                                                     "r0_ohm: {poly: [0.04, -0.02], axis: soc}\n";
    std::string y = test::simpleCellYaml() + kLoad;
    const size_t from = y.find("  cell:\n"), to = y.find("hardware:");
    y.replace(from, to - from, "  cell: {preset: bad_cell}\n");
    std::ofstream(dir / "s.yaml") << y;
  }
  const std::string e = test::fileErrorOf(dir / "s.yaml");
  EXPECT_TRUE(has(e, "bad_cell.yaml:3:")) << e;
  EXPECT_TRUE(has(e, "r0_ohm: must be > 0")) << e;
  fs::remove_all(dir);
}

}  // namespace
}  // namespace packsim
