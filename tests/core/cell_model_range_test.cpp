// The cell model's own range, judged on the truth: a cell past the temperatures its data
// covers (a table over temperature holds its edge row beyond them) or past the onset of
// self-heating gets a `cell_model_range` event at the first tick it is beyond, a `model
// range` summary line and a `check` warning; a run inside every bound gets none.
#include <gtest/gtest.h>

#include "core/check/check.hpp"
#include "core/sim/cell_model_range.hpp"
#include "core/sim/simulation.hpp"
#include "core/sim/summary_text.hpp"
#include "test_support.hpp"

namespace packsim {
namespace {

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

std::vector<const Event*> rangeEvents(const RunResult& r) { return test::eventsOf(r, "cell_model_range"); }

// Cell 2 of 3 heated by 30 W with the BMS's over-temperature rule out of the way: it
// passes 80 C within a minute or so. The event's time is the first recorded tick the
// truth has it above 80 C (recorded every tick).
TEST(CellModelRange, ACellPastTheSelfHeatingOnsetIsNotedAtTheFirstTickBeyond) {
  const Scenario s = test::scenarioFromYaml(
      test::simpleCellYaml(3) + "load: {current_A: 1}\nrun: {duration_s: 200}\noutput: {interval_s: 0.01}\n"
      "bms: {protections: {overtemperature: {enabled: false}}}\n"
      "faults:\n  - {kind: hot_cell, cell: 2, heat_W: 30, at_s: 1}\n");
  const RunResult r = runScenario(s);
  const auto events = rangeEvents(r);
  ASSERT_EQ(events.size(), 1u);
  const Event& e = *events[0];
  EXPECT_TRUE(has(e.detail, "cell 2 at ")) << e.detail;
  EXPECT_TRUE(has(e.detail, "above 80 C, where a lithium-ion cell starts to heat itself")) << e.detail;
  const Recording& rec = r.rec;
  const size_t cells = static_cast<size_t>(rec.cells);
  double firstAbove = -1.0;
  for (size_t i = 0; i < rec.samples() && firstAbove < 0.0; ++i)
    for (size_t c = 0; c < cells; ++c)
      if (rec.cell_temp_C[i * cells + c] > kSelfHeatingOnset_C) firstAbove = rec.time_s[i];
  ASSERT_GT(firstAbove, 0.0) << "the cell never passed 80 C";
  EXPECT_NEAR(e.time_s, firstAbove, 1e-9);
  EXPECT_GT(r.summary.max_temp_C, kSelfHeatingOnset_C);
  const std::string text = formatSummary(s, r);
  EXPECT_TRUE(has(text, "model range     ")) << text;
  EXPECT_TRUE(has(text, e.detail)) << text;
  const CheckOutcome o = judge(s, r);
  bool warned = false;
  for (const std::string& w : o.warnings) warned = warned || w == "beyond the cell model: " + e.detail;
  EXPECT_TRUE(warned);
}

// System E's LTO cell holds R0 over temperature from -30 C to 45 C. At -35 C ambient
// the cells start below the grid: the event names the table, and the curve beyond it is
// the -30 C row, as the event says.
TEST(CellModelRange, AColdCellBelowItsTemperatureTableIsNotedAndTheTableHoldsItsEdgeRow) {
  const Scenario s = test::scenarioFromYaml(
      "name: cold\npack: {series: 2, initial_soc: 0.5, initial_temp_C: -35, cell: {preset: lto_20Ah}}\n"
      "ambient: {temp_C: -35}\nload: {current_A: 0}\nrun: {duration_s: 5}\n");
  const RunResult r = runScenario(s);
  const auto events = rangeEvents(r);
  ASSERT_EQ(events.size(), 1u);
  EXPECT_TRUE(has(events[0]->detail, "below -30 C, the bottom of the temperature data of pack.cell.r0_ohm: beyond it "
                                     "it holds its -30 C row"))
      << events[0]->detail;
  const Curve& r0 = s.pack.cell.r0_ohm;
  for (double soc : {0.1, 0.5, 0.9})
    EXPECT_EQ(r0.eval(soc, s.pack.cell.axisCapacity_Ah(), -35.0), r0.eval(soc, s.pack.cell.axisCapacity_Ah(), -30.0));
  EXPECT_NE(r0.eval(0.5, s.pack.cell.axisCapacity_Ah(), -29.0), r0.eval(0.5, s.pack.cell.axisCapacity_Ah(), -30.0));
}

TEST(CellModelRange, ARunInsideEveryBoundHasNoEventAndNoLine) {
  const Scenario s = test::scenarioFromYaml(test::simpleCellYaml(2) + test::kSimpleLoadYaml);
  const RunResult r = runScenario(s);
  EXPECT_TRUE(rangeEvents(r).empty());
  EXPECT_FALSE(has(formatSummary(s, r), "model range")) << formatSummary(s, r);
}

// The bounds themselves: a cell without tables over temperature has the self-heating
// onset alone; each bound is noted once.
TEST(CellModelRange, BoundsComeFromTheTablesAndEachIsNotedOnce) {
  const Scenario s = test::scenarioFromYaml(test::simpleCellYaml(1) + test::kSimpleLoadYaml);
  CellModelRange plain(s.pack.cell);
  ASSERT_EQ(plain.bounds().size(), 1u);
  EXPECT_EQ(plain.bounds()[0].temp_C, kSelfHeatingOnset_C);
  int notes = 0;
  const auto count = [&notes](const std::string&) { ++notes; };
  plain.tick(25.0, 79.9, {25.0, 79.9}, 1, count);
  EXPECT_EQ(notes, 0);
  plain.tick(25.0, 80.5, {25.0, 80.5}, 1, count);
  plain.tick(25.0, 90.0, {25.0, 90.0}, 1, count);
  EXPECT_EQ(notes, 1);
  const Scenario lto = test::scenarioFromYaml(
      "name: e\npack: {series: 1, cell: {preset: lto_20Ah}}\nload: {current_A: 1}\nrun: {duration_s: 1}\n");
  CellModelRange tabled(lto.pack.cell);
  ASSERT_EQ(tabled.bounds().size(), 3u);
  EXPECT_EQ(tabled.bounds()[0].temp_C, -30.0);
  EXPECT_FALSE(tabled.bounds()[0].above);
  EXPECT_EQ(tabled.bounds()[1].temp_C, 45.0);
  EXPECT_TRUE(tabled.bounds()[1].above);
}

}  // namespace
}  // namespace packsim
