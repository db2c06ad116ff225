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
  return test::writeTempFile("packsim_csv_columns", name, text);
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
  const fs::path f = writeCsv("semicolon.csv", "t;P_kW;note\n0;0,015;start\n2,5;-0,0025;regen\n");
  const Scenario s = withCsv("{file: " + f.string() + ", time_column: t, power_column: P_kW, scale: 1000}");
  EXPECT_EQ(s.load.quantity, LoadProfile::Quantity::Power_W);
  ASSERT_EQ(s.load.t_s, (std::vector<double>{0.0, 2.5}));
  EXPECT_DOUBLE_EQ(s.load.i_A[0], 15.0);
  EXPECT_DOUBLE_EQ(s.load.i_A[1], -2.5);
}

TEST(CsvColumns, DefaultColumnsAmongExtraOnes) {
  const fs::path f = writeCsv("extra.csv", "time_s,lap,current_A\n0,1,2\n5,1,3\n");
  const Scenario s = withCsv(f.string());
  EXPECT_EQ(s.load.i_A, (std::vector<double>{2.0, 3.0}));
}

TEST(CsvColumns, MissingColumnNamesTheColumnAndTheClosest) {
  const fs::path f = writeCsv("missing.csv", "Zeit,I_mA\n0,1\n1,2\n");
  const std::string e = errorOf("{file: " + f.string() + ", time_column: Zeit, current_column: I_ma}");
  EXPECT_NE(e.find("missing.csv:1:1: current_column: no column 'I_ma' in the header (columns as read: 'Zeit', 'I_mA'); "
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

// Excel's "CSV UTF-8" starts the file with a byte-order mark and ends lines with CRLF:
// read as the same table as the plain file (issue 28).
TEST(CsvColumns, ExcelUtf8ByteOrderMarkAndCrlfLineEndsAreRead) {
  const std::string table = "time_s,current_A\n0,1.5\n10,2.5\n";
  const Scenario plain = withCsv(writeCsv("plain.csv", table).string());
  std::string excel = "\xEF\xBB\xBF";
  for (const char ch : table) excel += ch == '\n' ? std::string("\r\n") : std::string(1, ch);
  const Scenario bom = withCsv(writeCsv("excel.csv", excel).string());
  EXPECT_EQ(bom.load.t_s, plain.load.t_s);
  EXPECT_EQ(bom.load.i_A, plain.load.i_A);
  EXPECT_EQ(bom.load.i_A, (std::vector<double>{1.5, 2.5}));
  // A quoted header after the mark, and named columns, too.
  const Scenario quoted =
      withCsv("{file: " + writeCsv("quoted.csv", "\xEF\xBB\xBF\"t\",\"I\"\r\n0,1.5\r\n10,2.5\r\n").string() +
              ", time_column: t, current_column: I}");
  EXPECT_EQ(quoted.load.i_A, plain.load.i_A);
}

// A header that differs from the expected one only in characters a terminal does not
// show: the message quotes the header as read with those characters escaped.
TEST(CsvColumns, HeaderMismatchShowsInvisibleCharactersEscaped) {
  const fs::path f = writeCsv("nbsp.csv", "time_s,current\xC2\xA0" "A\n0,1\n1,2\n");
  const std::string e = errorOf(f.string());
  EXPECT_NE(e.find("nbsp.csv:1:1: "), std::string::npos) << e;
  EXPECT_NE(e.find("the header as read is 'time_s,current\\xC2\\xA0A'"), std::string::npos) << e;
  const fs::path g = writeCsv("zwsp.csv", "t,\xE2\x80\x8BI\n0,1\n1,2\n");
  const std::string e2 = errorOf("{file: " + g.string() + ", time_column: t, current_column: I}");
  EXPECT_NE(e2.find("zwsp.csv:1:1: current_column: no column 'I' in the header (columns as read: 't', "
                    "'\\xE2\\x80\\x8BI')"),
            std::string::npos)
      << e2;
}

// Every CSV error names file:line and a column.
TEST(CsvColumns, StructuralErrorsNameLineAndColumn) {
  EXPECT_NE(errorOf(writeCsv("empty.csv", "# only a comment\n\n").string()).find("empty.csv:2:1: empty CSV"),
            std::string::npos);
  EXPECT_NE(errorOf(writeCsv("short.csv", "time_s,current_A\n0,1\n").string())
                .find("short.csv:2:1: time_s: a profile needs at least 2 points, got 1"),
            std::string::npos);
  const std::string wide = errorOf(writeCsv("wide.csv", "time_s,current_A\n0,1\n1,2,3\n").string());
  EXPECT_NE(wide.find("wide.csv:3:5: expected 2 columns"), std::string::npos) << wide;
  const std::string dir = errorOf(test::processTempDir("packsim_csv_columns").string());
  EXPECT_NE(dir.find("not a CSV file"), std::string::npos) << dir;
}

}  // namespace
}  // namespace packsim
