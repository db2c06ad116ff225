// Every class of bad input yields its own clear message naming file:line:column and
// the field, before the run starts.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "test_support.hpp"

namespace packsim {
namespace {

namespace fs = std::filesystem;

std::string errorOf(const std::string& yaml) { return test::yamlErrorOf(yaml); }

const std::string& kLoad = test::kSimpleLoadYaml;

TEST(ScenarioErrors, UnknownKeySuggestsClosest) {
  std::string y = test::simpleCellYaml() + kLoad;
  y.replace(y.find("capacity_Ah"), 11, "capcity_Ah");
  const std::string e = errorOf(y);
  EXPECT_NE(e.find("test.yaml:8:5: pack.cell.capcity_Ah: unknown key; did you mean 'capacity_Ah'?"), std::string::npos) << e;
}

TEST(ScenarioErrors, UnknownTopLevelSection) {
  const std::string e = errorOf(test::simpleCellYaml() + kLoad + "outptu: {interval_s: 1}\n");
  EXPECT_NE(e.find("outptu: unknown key; did you mean 'output'?"), std::string::npos) << e;
}

TEST(ScenarioErrors, ResetRequestTakesNoTarget) {
  const std::string e = errorOf(test::simpleCellYaml() + kLoad + "faults:\n  - {kind: reset_request, at_s: 1, cell: 1}\n");
  EXPECT_NE(e.find("cell: unknown key"), std::string::npos) << e;
  const std::string k = errorOf(test::simpleCellYaml() + kLoad + "faults:\n  - {kind: reset_requst, at_s: 1}\n");
  EXPECT_NE(k.find("did you mean 'reset_request'?"), std::string::npos) << k;
}

TEST(ScenarioErrors, WrongType) {
  std::string y = test::simpleCellYaml() + kLoad;
  y.replace(y.find("r0_ohm: 0.02"), 12, "r0_ohm: low");
  const std::string e = errorOf(y);
  EXPECT_NE(e.find("test.yaml:10:13: pack.cell.r0_ohm: expected a number, got 'low'"), std::string::npos) << e;
}

TEST(ScenarioErrors, MissingRequiredField) {
  std::string y = test::simpleCellYaml() + kLoad;
  y.erase(y.find("    capacity_Ah: 2.0\n"), 21);
  const std::string e = errorOf(y);
  EXPECT_NE(e.find("pack.cell: missing required key 'capacity_Ah'"), std::string::npos) << e;
  EXPECT_NE(e.find("test.yaml:8:5"), std::string::npos) << e;
}

TEST(ScenarioErrors, OutOfRangeNamesAllowedRange) {
  std::string y = test::simpleCellYaml() + kLoad;
  y.replace(y.find("initial_soc: 0.8"), 16, "initial_soc: 1.3");
  const std::string e = errorOf(y);
  EXPECT_NE(e.find("test.yaml:5:16: pack.initial_soc: 1.3 is out of range; allowed [0, 1]"), std::string::npos) << e;
}

TEST(ScenarioErrors, BadChoiceSuggests) {
  const std::string e = errorOf(test::simpleCellYaml() +
                                "load: {points: {time_s: [0, 10], current_A: [1, 2]}, interpolation: linaer}\n");
  EXPECT_NE(e.find("load.interpolation: 'linaer' is not one of: step, linear (did you mean 'linear'?)"), std::string::npos) << e;
}

TEST(ScenarioErrors, YamlSyntaxError) {
  const std::string e = errorOf("name: x\npack: {series: 2\n");
  EXPECT_NE(e.find("test.yaml:3:1: YAML syntax error"), std::string::npos) << e;
}

TEST(ScenarioErrors, ThresholdBeyondSensorRange) {
  const std::string e = errorOf(test::simpleCellYaml() + kLoad + "bms: {protections: {overcurrent_discharge: {threshold_A: 90}}}\n");
  EXPECT_NE(e.find("beyond the current sensor's range"), std::string::npos) << e;
}

class CsvErrors : public ::testing::Test {
 protected:
  std::string run(const std::string& csv) {
    const fs::path dir = test::processTempDir("packsim_csv");
    fs::create_directories(dir);
    std::ofstream(dir / "p.csv") << csv;
    return errorOf(test::simpleCellYaml() + "load: {csv: " + (dir / "p.csv").string() + "}\n");
  }
};

TEST_F(CsvErrors, NotANumber) {
  const std::string e = run("time_s,current_A\n0,1\n10,abc\n");
  EXPECT_NE(e.find("p.csv:3:4: current_A: 'abc' is not a finite number"), std::string::npos) << e;
}

TEST_F(CsvErrors, TimeNotIncreasing) {
  const std::string e = run("time_s,current_A\n0,1\n10,2\n10,3\n");
  EXPECT_NE(e.find("p.csv:4:1: time_s: time must increase strictly: 10 after 10"), std::string::npos) << e;
}

TEST_F(CsvErrors, WrongHeader) {
  const std::string e = run("t,I\n0,1\n");
  EXPECT_NE(e.find("p.csv:1:1: expected the header 'time_s,current_A'"), std::string::npos) << e;
}

TEST_F(CsvErrors, WrongColumnCount) {
  const std::string e = run("time_s,current_A\n0,1,2\n");
  EXPECT_NE(e.find("p.csv:2: expected 2 columns"), std::string::npos) << e;
}

// The CLI turns a bad scenario into exit status 2 and leaves no result file.
TEST(CliErrors, BadScenarioExitsTwoAndWritesNothing) {
  const fs::path dir = test::processTempDir("packsim_cli_bad");
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::ofstream(dir / "bad.yaml") << "name: bad\npack: {series: 2, cell: {capacity_Ah: -1, ocv_V: 3.7, r0_ohm: 0.01}}\n"
                                     "load: {current_A: 1}\nrun: {duration_s: 1}\n";
  const std::string cmd = std::string(PACKSIM_BINARY) + " run " + (dir / "bad.yaml").string() + " -o " +
                          (dir / "out.h5").string() + " 2> " + (dir / "err.txt").string();
  const int rc = std::system(cmd.c_str());
  EXPECT_EQ(WEXITSTATUS(rc), 2);
  EXPECT_FALSE(fs::exists(dir / "out.h5"));
  EXPECT_FALSE(test::temporaryOfExists(dir / "out.h5"));
  std::ifstream err(dir / "err.txt");
  const std::string msg((std::istreambuf_iterator<char>(err)), {});
  EXPECT_NE(msg.find("bad.yaml:2:39: pack.cell.capacity_Ah: -1 is out of range; allowed > 0"), std::string::npos) << msg;
  fs::remove_all(dir);
}

}  // namespace
}  // namespace packsim
