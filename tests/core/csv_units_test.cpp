// A logger's CSV as users bring it: time in ms, current in mA, discharge counted
// negative. Read as it stands, each gives a plausible run of the wrong size or sign, so
// a unit in a column's name needs its scale said, and a profile that charges the pack
// on balance is a warning naming the scale that flips it.
#include <gtest/gtest.h>

#include <filesystem>

#include "core/scenario/column_units.hpp"
#include "core/scenario/scenario_warnings.hpp"
#include "test_support.hpp"

namespace packsim {
namespace {

namespace fs = std::filesystem;

fs::path writeCsv(const std::string& name, const std::string& text) {
  return test::writeTempFile("packsim_csv_units", name, text);
}

std::string csvYaml(const std::string& spec) { return test::simpleCellYaml() + "load: {csv: " + spec + "}\n"; }

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

std::string signWarning(const Scenario& s) {
  for (const std::string& w : scenarioWarnings(s))
    if (has(w, "charges the pack on balance")) return w;
  return "";
}

TEST(CsvUnits, UnitsAreReadFromTheEndOfAColumnName) {
  EXPECT_EQ(timeUnitOfName("t_ms").factor, 1e-3);
  EXPECT_EQ(timeUnitOfName("Time (ms)").unit, "ms");
  EXPECT_EQ(timeUnitOfName("time [min]").factor, 60.0);
  EXPECT_EQ(timeUnitOfName("time_s").factor, 1.0);
  EXPECT_EQ(timeUnitOfName("time").factor, 0.0);
  EXPECT_EQ(timeUnitOfName("Zeit").factor, 0.0);
  EXPECT_EQ(valueUnitOfName("I [mA]", false).factor, 1e-3);
  EXPECT_EQ(valueUnitOfName("current_A", false).factor, 1.0);
  EXPECT_EQ(valueUnitOfName("I_bat", false).factor, 0.0);
  EXPECT_EQ(valueUnitOfName("P_kW", true).factor, 1e3);
  EXPECT_EQ(valueUnitOfName("P_kW", false).factor, 0.0);  // a current column named in kW: not a current unit
}

TEST(CsvUnits, ATimeColumnInMillisecondsNeedsItsScale) {
  const fs::path f = writeCsv("ms.csv", "t_ms,I\n0,1\n500,2\n1000,3\n");
  const std::string spec = "{file: " + f.string() + ", time_column: t_ms, current_column: I";
  const std::string e = test::yamlErrorOf(csvYaml(spec + "}"));
  EXPECT_TRUE(has(e, "load.csv.time_column: the column 't_ms' is named in ms and packsim reads s: add time_scale: "
                     "0.001 (or time_scale: 1 if its values are in s)"))
      << e;
  const Scenario scaled = test::scenarioFromYaml(csvYaml(spec + ", time_scale: 0.001}"));
  EXPECT_EQ(scaled.load.t_s, (std::vector<double>{0.0, 0.5, 1.0}));
  const Scenario asIs = test::scenarioFromYaml(csvYaml(spec + ", time_scale: 1}"));  // the user's word
  EXPECT_EQ(asIs.load.t_s, (std::vector<double>{0.0, 500.0, 1000.0}));
}

TEST(CsvUnits, ACurrentColumnInMilliampsNeedsItsScale) {
  const fs::path f = writeCsv("ma.csv", "time_s,I [mA]\n0,1500\n10,2500\n");
  const std::string spec = "{file: " + f.string() + ", current_column: 'I [mA]'";
  const std::string e = test::yamlErrorOf(csvYaml(spec + "}"));
  EXPECT_TRUE(has(e, "load.csv.current_column: the column 'I [mA]' is named in mA and packsim reads A: add scale: "
                     "0.001"))
      << e;
  EXPECT_EQ(test::scenarioFromYaml(csvYaml(spec + ", scale: 0.001}")).load.i_A, (std::vector<double>{1.5, 2.5}));
}

// Discharge logged negative: the profile's mean over the run is below 0. The warning
// names the scale that flips it; flipped, the same log gives none.
TEST(CsvUnits, AProfileThatChargesOnBalanceIsAWarningNamingTheFlip) {
  const fs::path f = writeCsv("neg.csv", "time_s,I\n0,-2\n50,1\n60,-2\n100,-2\n");
  const std::string spec = "{file: " + f.string() + ", current_column: I";
  const std::string w = signWarning(test::scenarioFromYaml(csvYaml(spec + "}")));
  // mean over 100 s: (-2 * 50 + 1 * 10 - 2 * 40) / 100 = -1.7 A (step interpolation)
  EXPECT_TRUE(has(w, "its mean is -1.7 A over the run's first 100 s")) << w;
  EXPECT_TRUE(has(w, "needs load.csv.scale: -1")) << w;
  EXPECT_EQ(signWarning(test::scenarioFromYaml(csvYaml(spec + ", scale: -1}"))), "");
  // Points written in the scenario: the same judgement, without a CSV scale to name.
  const std::string points = signWarning(test::scenarioFromYaml(
      test::simpleCellYaml() + "load: {points: {time_s: [0, 10], current_A: [-1, 2]}}\nrun: {duration_s: 10}\n"));
  EXPECT_TRUE(has(points, "needs its values' signs flipped")) << points;
  // A constant charge current is meant as such.
  EXPECT_EQ(signWarning(test::scenarioFromYaml(test::simpleCellYaml() + "load: {current_A: -1}\nrun: {duration_s: 10}\n")),
            "");
}

}  // namespace
}  // namespace packsim
