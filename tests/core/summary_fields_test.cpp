// The summary-field table (core/sim/summary_fields.hpp) against what the writer writes,
// what summary.csv leads with and what docs/results.md documents.
#include "core/sim/summary_fields.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>

#include "core/batch/batch_runner.hpp"
#include "core/io/hdf5_writer.hpp"
#include "core/scenario/overrides.hpp"
#include "core/sim/simulation.hpp"
#include "core/sim/summary_lines.hpp"
#include "core/sim/summary_text.hpp"
#include "core/sim/vehicle_text.hpp"
#include "test_support.hpp"

namespace packsim {
namespace {

namespace fs = std::filesystem;

// The /summary attribute names of a short run of a bundled scenario, as written.
std::set<std::string> writtenNames(const std::string& name, const std::string& file, Summary* summary) {
  const Scenario s = loadScenarioFileWithOverrides(test::scenarioDir() + "/" + name, {{"run.duration_s", "4"}});
  const RunResult r = runScenario(s);
  *summary = r.summary;
  writeResultHdf5(file, s, r);
  std::set<std::string> names;
  for (const auto& [k, v] : readResultSummary(file, nullptr)) names.insert(k);
  return names;
}

std::set<std::string> rowsFor(const Summary& m) {
  std::set<std::string> names;
  for (const SummaryField& f : summaryFields())
    if (!f.present || f.present(m)) names.insert(f.name);
  return names;
}

TEST(SummaryFields, TheFileHoldsExactlyTheRowsOfTheRun) {
  const fs::path dir = test::processTempDir("summary_fields");
  Summary m;
  const std::set<std::string> plain = writtenNames("eco_marathon_12s.yaml", (dir / "a.h5").string(), &m);
  EXPECT_FALSE(m.vehicle.present);
  ASSERT_TRUE(m.balance.present);  // system A has passive balancing
  EXPECT_EQ(plain, rowsFor(m));
  EXPECT_EQ(plain.count("vehicle_distance_km"), 0u);
  EXPECT_EQ(plain.count("balance_bled_Ah"), 1u);
  EXPECT_EQ(plain.count("duration_s"), 1u);
  const std::set<std::string> vehicle = writtenNames("vehicle/solar_car_28s15p_stage.yaml", (dir / "b.h5").string(), &m);
  ASSERT_TRUE(m.vehicle.present);
  ASSERT_FALSE(m.balance.present);  // system B balances actively, if at all
  EXPECT_EQ(vehicle, rowsFor(m));
  EXPECT_EQ(vehicle.count("balance_bled_Ah"), 0u);
  EXPECT_EQ(vehicle.size(), plain.size() + 7 - 8);  // the seven vehicle figures, without the eight balancing ones
}

TEST(SummaryFields, NamesAreUniqueAndTheCsvColumnsAreTheRankedRowsInOrder) {
  std::set<std::string> names;
  std::set<int> ranks;
  int ranked = 0;
  for (const SummaryField& f : summaryFields()) {
    EXPECT_TRUE(names.insert(f.name).second) << f.name << " twice";
    if (f.csv_rank > 0) {
      ++ranked;
      EXPECT_TRUE(ranks.insert(f.csv_rank).second) << f.name << ": rank " << f.csv_rank << " twice";
    }
  }
  ASSERT_EQ(ranked, 21);
  EXPECT_EQ(*ranks.begin(), 1);
  EXPECT_EQ(*ranks.rbegin(), ranked);  // 1..n, no gap
  // summary.csv's reading order as docs/batch.md describes it: the run's end first.
  const std::vector<std::string> lead = summaryCsvLeadingColumns();
  ASSERT_EQ(lead.size(), 21u);
  EXPECT_EQ(lead[0], "duration_s");
  EXPECT_EQ(lead[1], "tripped");
  EXPECT_EQ(lead[3], "trip_reason");
  EXPECT_EQ(lead[20], "final_soc_max");
}

TEST(SummaryFields, DocsResultsNamesEveryRow) {
  const fs::path docs = fs::canonical(test::scenarioDir()).parent_path() / "docs" / "results.md";
  std::ifstream in(docs);
  ASSERT_TRUE(in) << docs;
  std::string line, summaryRow;
  while (std::getline(in, line))
    if (line.rfind("| `/summary` |", 0) == 0) summaryRow = line;
  ASSERT_FALSE(summaryRow.empty()) << "no /summary row in " << docs;
  for (const SummaryField& f : summaryFields()) {
    const std::string name = f.name;
    // soc_error_{coulomb,ekf}_{max,rms,end} stands for its six names.
    const bool braced = name.rfind("soc_error_coulomb_", 0) == 0 || (name.rfind("soc_error_ekf_", 0) == 0 && name.find("group") == std::string::npos);
    if (braced) {
      EXPECT_NE(summaryRow.find("`soc_error_{coulomb,ekf}_{max,rms,end}`"), std::string::npos);
      continue;
    }
    EXPECT_NE(summaryRow.find("`" + name + "`"), std::string::npos) << name << " is not in docs/results.md's /summary row";
  }
}

// The printed summary is a table of lines too (summary_text.cpp, vehicle_text.cpp): each
// line names the figures it prints. Every /summary figure is printed by exactly one
// line, and a line names only figures of the table -- so a new figure fails here until
// a line prints it.
TEST(SummaryFields, EveryFigureIsPrintedByOneSummaryLine) {
  std::set<std::string> table;
  for (const SummaryField& f : summaryFields()) table.insert(f.name);
  std::map<std::string, std::string> printedBy;  // figure -> the line's label
  auto take = [&](const char* label, const char* fields) {
    EXPECT_LT(std::string(label).size(), LineWriter::kLabelColumns) << label;
    std::istringstream names(fields);
    for (std::string n; names >> n;) {
      EXPECT_EQ(table.count(n), 1u) << "the '" << label << "' line names " << n << ", no /summary figure";
      EXPECT_TRUE(printedBy.emplace(n, label).second) << n << " on the '" << label << "' and the '" << printedBy[n] << "' line";
    }
  };
  for (const SummaryLine& l : summaryLines()) take(l.label, l.fields);
  for (const VehicleLine& l : vehicleLines()) take(l.label, l.fields);
  for (const std::string& n : table) EXPECT_EQ(printedBy.count(n), 1u) << n << " is on no summary line";
  EXPECT_EQ(printedBy.at("energy_stranded_Wh"), "energy left");
  EXPECT_EQ(printedBy.at("vehicle_time_lost_s"), "time lost");
}

}  // namespace
}  // namespace packsim
