// A quoted scalar is text in YAML (`capacity_Ah: "5"`): every key that takes a number or
// true/false refuses it with one error naming the field, as --set and Python overrides
// do (a JSON string), instead of reading it as the number (core/scenario/yaml_map.hpp).
#include <gtest/gtest.h>

#include "core/scenario/overrides.hpp"
#include "test_support.hpp"

namespace packsim {
namespace {

const std::string kBase = test::simpleCellYaml() + test::kSimpleLoadYaml;

std::string withLine(const std::string& from, const std::string& to) {
  std::string y = kBase;
  const size_t at = y.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return y.replace(at, from.size(), to);
}

TEST(QuotedValues, ANumberInQuotesIsRefusedNamingTheField) {
  // Was: accepted, as 2.0 Ah (and `show` printed it as a number from the file).
  for (const char* q : {"\"2.0\"", "'2.0'", "!!str 2.0"}) {
    const std::string e = test::yamlErrorOf(withLine("capacity_Ah: 2.0", std::string("capacity_Ah: ") + q));
    EXPECT_NE(e.find("test.yaml:8:18: pack.cell.capacity_Ah: expected a number, got the text \"2.0\" (quoted"),
              std::string::npos) << e;
  }
  // In a list, a table row and a boolean alike.
  EXPECT_NE(test::yamlErrorOf(withLine("at_groups: [1]", "at_groups: [\"1\"]")).find("hardware.thermistors.at_groups[0]: expected a number, got the text"),
            std::string::npos);
  const std::string table = withLine("ocv_V: {poly: [0.8, 3.4]}", "ocv_V: {x: [0, 1], temp_C: [25], y: [[3.4, '4.2']]}");
  EXPECT_NE(test::yamlErrorOf(table).find("pack.cell.ocv_V.y: row 1 (temp_C 25): expected a number, got the text \"4.2\""),
            std::string::npos) << test::yamlErrorOf(table);
  const std::string flag = kBase + "output: {bus_trace: \"true\"}\n";
  EXPECT_NE(test::yamlErrorOf(flag).find("output.bus_trace: expected true or false, got the text \"true\""), std::string::npos)
      << test::yamlErrorOf(flag);
}

TEST(QuotedValues, AnOverrideGivenAsAStringIsRefusedToo) {
  // `--set pack.cell.capacity_Ah='"5"'`, or a Python override {"pack.cell.capacity_Ah": "5"} (JSON "5").
  const std::string e = test::scenarioErrorOf([] { loadScenarioWithOverrides(kBase, {{"pack.cell.capacity_Ah", "\"5\""}}, "test.yaml", "."); });
  EXPECT_NE(e.find("pack.cell.capacity_Ah: expected a number, got the text \"5\""), std::string::npos) << e;
  EXPECT_NE(e.find("after override pack.cell.capacity_Ah = \"5\""), std::string::npos) << e;
  // Plain, it loads.
  EXPECT_DOUBLE_EQ(loadScenarioWithOverrides(kBase, {{"pack.cell.capacity_Ah", "5"}}, "test.yaml", ".").pack.cell.capacity_Ah, 5.0);
}

TEST(QuotedValues, TextKeysStillTakeQuotes) {
  const Scenario s = test::scenarioFromYaml(withLine("name: simple", "name: \"24s4p: 2026\""));
  EXPECT_EQ(s.name, "24s4p: 2026");
}

}  // namespace
}  // namespace packsim
