// CSV load profiles as users have them: columns picked by name, extra columns ignored,
// commas or semicolons (with decimal commas), a scale for other units; errors name
// file:line:column and the column.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "test_support.hpp"

namespace packsim {
namespace {

namespace fs = std::filesystem;

fs::path writeCsv(const std::string& name, const std::string& text) {
  const fs::path dir = test::processTempDir("packsim_csv_columns");
  fs::create_directories(dir);
  std::ofstream(dir / name) << text;
  return dir / name;
}

Scenario withCsv(const std::string& csvYaml) {
  return test::scenarioFromYaml(test::simpleCellYaml() + "load: {csv: " + csvYaml + "}\n");
}

std::string errorOf(const std::string& csvYaml) {
  return test::scenarioErrorOf([&] { withCsv(csvYaml); });
}

TEST(CsvColumns, PicksColumnsByNameIgnoresOthersAndScales) {
  const fs::path f = writeCsv("logger.csv",
                              "sample,Zeit,speed_kmh,I_mA,T_amb\n"
                              "1,0,0,1500,20\n"
                              "2,10.5,31,-2500,20\n"
                              "3,20,40,0,21\n");
  const Scenario s =
      withCsv("{file: " + f.string() + ", time_column: Zeit, current_column: I_mA, scale: 0.001}");
  ASSERT_EQ(s.load.t_s, (std::vector<double>{0.0, 10.5, 20.0}));
  ASSERT_EQ(s.load.i_A.size(), 3u);
  EXPECT_DOUBLE_EQ(s.load.i_A[0], 1.5);
  EXPECT_DOUBLE_EQ(s.load.i_A[1], -2.5);
  EXPECT_EQ(s.load.quantity, LoadProfile::Quantity::Current_A);
}

TEST(CsvColumns, SemicolonsWithDecimalCommasAndAPowerColumn) {
  const fs::path f = writeCsv("semicolon.csv", "t;P_kW;note\n0;1,5;start\n2,5;-0,25;regen\n");
  const Scenario s = withCsv("{file: " + f.string() + ", time_column: t, power_column: P_kW, scale: 1000}");
  EXPECT_EQ(s.load.quantity, LoadProfile::Quantity::Power_W);
  ASSERT_EQ(s.load.t_s, (std::vector<double>{0.0, 2.5}));
  EXPECT_DOUBLE_EQ(s.load.i_A[0], 1500.0);
  EXPECT_DOUBLE_EQ(s.load.i_A[1], -250.0);
}

TEST(CsvColumns, DefaultColumnsAmongExtraOnes) {
  const fs::path f = writeCsv("extra.csv", "time_s,lap,current_A\n0,1,2\n5,1,3\n");
  const Scenario s = withCsv(f.string());
  EXPECT_EQ(s.load.i_A, (std::vector<double>{2.0, 3.0}));
}

TEST(CsvColumns, MissingColumnNamesTheColumnAndTheClosest) {
  const fs::path f = writeCsv("missing.csv", "Zeit,I_mA\n0,1\n1,2\n");
  const std::string e = errorOf("{file: " + f.string() + ", time_column: Zeit, current_column: I_ma}");
  EXPECT_NE(e.find("missing.csv:1:1: current_column: no column 'I_ma' in the header (columns: Zeit, I_mA); "
                   "did you mean 'I_mA'?"),
            std::string::npos)
      << e;
}

TEST(CsvColumns, BadNumberNamesLineColumnAndColumnName) {
  const fs::path f = writeCsv("badnum.csv", "t;x;I\n0;9;1\n1;9;zwei\n");
  const std::string e = errorOf("{file: " + f.string() + ", time_column: t, current_column: I}");
  EXPECT_NE(e.find("badnum.csv:3:5: I: 'zwei' is not a finite number"), std::string::npos) << e;
}

TEST(CsvColumns, MappingKeysAreChecked) {
  const fs::path f = writeCsv("keys.csv", "time_s,current_A\n0,1\n1,2\n");
  EXPECT_NE(errorOf("{file: " + f.string() + ", current_colum: x}").find("current_column"), std::string::npos);
  EXPECT_NE(errorOf("{file: " + f.string() + ", current_column: a, power_column: b}").find("power_column"),
            std::string::npos);
  EXPECT_NE(errorOf("{file: " + f.string() + ", scale: 0}").find("scale"), std::string::npos);
  EXPECT_NE(errorOf("{file: nope.csv}").find("file not found"), std::string::npos);
}

}  // namespace
}  // namespace packsim
