// Scenario overrides: dotted keys set what they name, create optional keys, refuse
// paths that cannot exist, and loader errors on overridden fields name the override.
#include "core/scenario/overrides.hpp"

#include <gtest/gtest.h>

#include <filesystem>

#include "test_support.hpp"

namespace packsim {
namespace {

const std::string& kLoad = test::kSimpleLoadYaml;

std::string base() { return test::simpleCellYaml() + kLoad; }

Scenario withOverrides(const Overrides& o) { return loadScenarioWithOverrides(base(), o, "test.yaml", test::scenarioDir()); }

std::string errorOf(const Overrides& o) {
  return test::scenarioErrorOf([&] { withOverrides(o); });
}

TEST(Overrides, NoOverridesReturnsTheTextUnchanged) {
  EXPECT_EQ(applyOverrides(base(), {}, "test.yaml"), base());
  EXPECT_EQ(withOverrides({}).text, base());
}

TEST(Overrides, SetsExistingNestedValues) {
  const Scenario s = withOverrides({{"pack.cell.capacity_Ah", "3.5"}, {"pack.initial_soc", "0.5"}, {"seed", "77"}});
  EXPECT_DOUBLE_EQ(s.pack.cell.capacity_Ah, 3.5);
  EXPECT_DOUBLE_EQ(s.pack.initial_soc, 0.5);
  EXPECT_EQ(s.run.seed, 77u);
  // Everything else is as in the file.
  const Scenario ref = withOverrides({});
  EXPECT_EQ(s.pack.series, ref.pack.series);
  EXPECT_DOUBLE_EQ(s.run.duration_s, ref.run.duration_s);
  // The stored text is the merged scenario, which loads to the same values on its own.
  const Scenario again = loadScenarioText(s.text, "merged.yaml", test::scenarioDir());
  EXPECT_DOUBLE_EQ(again.pack.cell.capacity_Ah, 3.5);
  EXPECT_EQ(again.run.seed, 77u);
}

TEST(Overrides, CreatesOptionalKeysAndSections) {
  const Scenario s = withOverrides({{"run.stop_after_trip_s", "5"}, {"output.interval_s", "2"}});
  EXPECT_DOUBLE_EQ(s.run.stop_after_trip_s, 5.0);
  EXPECT_DOUBLE_EQ(s.output.interval_s, 2.0);
}

TEST(Overrides, ListElementsByIndexInBothSpellings) {
  const Scenario a = withOverrides({{"pack.cell.rc_pairs.0.r_ohm", "0.03"}});
  const Scenario b = withOverrides({{"pack.cell.rc_pairs[0].r_ohm", "0.03"}});
  ASSERT_EQ(a.pack.cell.rc.size(), 1u);
  EXPECT_DOUBLE_EQ(a.pack.cell.rc[0].r_ohm, 0.03);
  EXPECT_DOUBLE_EQ(b.pack.cell.rc[0].r_ohm, 0.03);
}

TEST(Overrides, ValuesAreYamlIncludingWholeMappingsAndLists) {
  // A mapping value replaces the mapping: the constant load becomes a segment list.
  const Scenario s = withOverrides({{"load", "{segments: [{duration_s: 4, current_A: 2}, {duration_s: 6, current_A: 0}]}"},
                                    {"run.duration_s", "10"}});
  EXPECT_FALSE(s.load.isConstant());
  EXPECT_DOUBLE_EQ(s.load.duration_s(), 10.0);
  // JSON is YAML: what Python sends.
  const Scenario j = withOverrides({{"pack.cell.rc_pairs", "[{\"r_ohm\": 0.02, \"tau_s\": 5.0}, {\"r_ohm\": 0.01, \"tau_s\": 50}]"}});
  EXPECT_EQ(j.pack.cell.rc.size(), 2u);
}

TEST(Overrides, LaterKeysWin) {
  EXPECT_DOUBLE_EQ(withOverrides({{"pack.cell.capacity_Ah", "3"}, {"pack.cell.capacity_Ah", "4"}}).pack.cell.capacity_Ah, 4.0);
}

TEST(Overrides, PathsThatCannotExistAreErrors) {
  EXPECT_NE(errorOf({{"pack.series.x", "1"}}).find("pack.series.x: pack.series is a single value, not a mapping"),
            std::string::npos)
      << errorOf({{"pack.series.x", "1"}});
  // The scalar's place in the original file is named.
  EXPECT_NE(errorOf({{"pack.series.x", "1"}}).find("test.yaml:4:"), std::string::npos);
  EXPECT_NE(errorOf({{"pack.cell.rc_pairs.3.r_ohm", "1"}}).find("has 1 element(s); index 3 is out of range"),
            std::string::npos);
  EXPECT_NE(errorOf({{"pack.cell.x.0", "1"}}).find("pack.cell.x is not set, not a list"), std::string::npos) << errorOf({{"pack.cell.x.0", "1"}});
  EXPECT_NE(errorOf({{"pack..cell", "1"}}).find("empty component"), std::string::npos);
  EXPECT_NE(errorOf({{"", "1"}}).find("override key is empty"), std::string::npos);
  EXPECT_NE(errorOf({{"pack.cell.rc_pairs[x]", "1"}}).find("'x' is not a list index"), std::string::npos);
  EXPECT_NE(errorOf({{"pack.cell.rc_pairs[0", "1"}}).find("unbalanced"), std::string::npos);
  EXPECT_NE(errorOf({{"pack.cell.capacity_Ah", "[1, 2"}}).find("is not valid YAML"), std::string::npos);
}

TEST(Overrides, LoaderErrorsNameTheOverride) {
  // A typo in the key: the strict loader suggests the closest key, and says which override.
  const std::string typo = errorOf({{"pack.cell.capcity_Ah", "3"}});
  EXPECT_NE(typo.find("pack.cell.capcity_Ah: unknown key; did you mean 'capacity_Ah'? (after override pack.cell.capcity_Ah = 3)"),
            std::string::npos)
      << typo;
  EXPECT_EQ(typo.find("test.yaml:"), 0u) << typo;
  const std::string range = errorOf({{"pack.initial_soc", "1.5"}});
  EXPECT_NE(range.find("pack.initial_soc: 1.5 is out of range; allowed [0, 1] (after override pack.initial_soc = 1.5)"),
            std::string::npos)
      << range;
  try {
    withOverrides({{"pack.initial_soc", "1.5"}});
    FAIL() << "no error";
  } catch (const ScenarioError& e) {
    EXPECT_EQ(e.file(), "test.yaml");
    EXPECT_EQ(e.field(), "pack.initial_soc");
    EXPECT_EQ(e.line(), 0);
  }
}

TEST(Overrides, ErrorsInUntouchedFieldsKeepTheirOriginalPosition) {
  std::string y = base();
  y.replace(y.find("r0_ohm: 0.02"), 12, "r0_ohm: low");
  try {
    loadScenarioWithOverrides(y, {{"pack.cell.capacity_Ah", "3"}}, "test.yaml", test::scenarioDir());
    FAIL() << "no error";
  } catch (const ScenarioError& e) {
    EXPECT_EQ(std::string(e.what()).find("test.yaml:10:13: pack.cell.r0_ohm: expected a number, got 'low'"), 0u) << e.what();
  }
}

TEST(Overrides, ACrossFieldErrorOnAnUntouchedFieldPointsIntoTheOriginalText) {
  // The overrides edit the parsed tree, so the loader still sees every original node
  // with its line and column: the error sits where `output` is written (line 21).
  const std::string y = "# a comment the emitted text would lose\n\n" + base() + "output: {interval_s: 0.5}\n";
  const std::string e =
      test::scenarioErrorOf([&] { loadScenarioWithOverrides(y, {{"bms.tick_ms", "1000"}}, "test.yaml", test::scenarioDir()); });
  EXPECT_EQ(e.find("test.yaml:23:"), 0u) << e;
  EXPECT_NE(e.find("output.interval_s: interval_s = 0.5 s is not a whole number of BMS ticks (bms.tick_ms 1000)"),
            std::string::npos) << e;
  EXPECT_NE(e.find("at least 1"), std::string::npos) << e;
}

TEST(Overrides, FileVersionResolvesCsvAgainstTheFileFolder) {
  // The bundled default reads profiles/…csv relative to its own folder, whatever the cwd.
  const std::string path = test::scenarioDir() + "/eco_marathon_12s.yaml";
  const auto cwd = std::filesystem::current_path();
  std::filesystem::current_path(std::filesystem::temp_directory_path());
  Scenario s;
  EXPECT_NO_THROW(s = loadScenarioFileWithOverrides(path, {{"load.laps", "2"}}));
  std::filesystem::current_path(cwd);
  const Scenario full = loadScenarioFile(path);
  EXPECT_NEAR(s.load.duration_s() * 5.0, full.load.duration_s(), 1e-9);
  EXPECT_EQ(s.file, path);
}

}  // namespace
}  // namespace packsim
