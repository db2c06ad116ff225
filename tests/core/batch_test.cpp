// Sweeps (core/batch/sweep) and the batch runner (core/batch/batch_runner): expansion
// of grid / zip / Monte Carlo, strict errors, one result per case, the summary CSV,
// resume, a failing case recorded while the others finish, the CLI's exit status.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "core/batch/batch_runner.hpp"
#include "core/batch/case_inputs.hpp"
#include "core/batch/drawn_inputs.hpp"
#include "core/batch/sweep.hpp"
#include "core/scenario/overrides.hpp"
#include "core/scenario/scenario_error.hpp"
#include "test_support.hpp"

namespace packsim {
namespace {

namespace fs = std::filesystem;

// A scratch folder holding a small base scenario (fast: 4 cells, 20 s).
struct Scratch {
  fs::path dir;
  Scratch() {
    dir = fs::temp_directory_path() / ("packsim_batch_" + std::to_string(::getpid()) + "_" +
                                       ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir);
    fs::create_directories(dir);
    std::ofstream(dir / "base.yaml") << test::simpleCellYaml(4) << "load: {current_A: 3}\nrun: {duration_s: 20}\n";
  }
  ~Scratch() { fs::remove_all(dir); }
  std::string write(const std::string& name, const std::string& text) const {
    std::ofstream(dir / name) << text;
    return (dir / name).string();
  }
};

std::string readFile(const fs::path& p) {
  std::ifstream in(p);
  std::ostringstream os;
  os << in.rdbuf();
  return os.str();
}

std::vector<std::string> lines(const std::string& s) {
  std::vector<std::string> out;
  std::istringstream in(s);
  for (std::string l; std::getline(in, l);) out.push_back(l);
  return out;
}

std::string field(const CaseOutcome& o, const std::string& name) {
  for (const auto& kv : o.summary)
    if (kv.first == name) return kv.second;
  ADD_FAILURE() << "no summary field " << name;
  return "nan";
}

std::string sweepError(const Scratch& sc, const std::string& text) {
  try {
    loadSweepFile(sc.write("sweep.yaml", text));
  } catch (const ScenarioError& e) {
    return e.what();
  }
  return "no error";
}

TEST(Sweep, GridZipAndMonteCarloExpandToTheirProduct) {
  Scratch sc;
  const Sweep sw = loadSweepFile(sc.write("s.yaml",
                                          "base: base.yaml\n"
                                          "grid:\n  pack.cell.capacity_Ah: [1.5, 2.0]\n  bms.tick_ms: [10, 100, 1000]\n"
                                          "zip:\n  pack.initial_soc: [0.9, 0.7]\n  ambient.temp_C: [20, 30]\n"
                                          "monte_carlo: {samples: 3, master_seed: 5}\n"));
  ASSERT_EQ(sw.cases.size(), 2u * 3u * 2u * 3u);
  EXPECT_EQ(sw.keys, (std::vector<std::string>{"pack.cell.capacity_Ah", "bms.tick_ms", "pack.initial_soc",
                                                "ambient.temp_C", "seed"}));
  EXPECT_EQ(sw.name, "s");
  EXPECT_EQ(sw.output_dir, (sc.dir / "s-results").lexically_normal().string());
  // The first grid key varies slowest, the seed fastest; zipped keys move together.
  const SweepCase& c = sw.cases[7];  // = (0, 1, 0, 1) in radix (2, 3, 2, 3)
  EXPECT_EQ(c.id, "0007");
  ASSERT_EQ(c.params.size(), 5u);
  EXPECT_EQ(c.params[0].second, "1.5");
  EXPECT_EQ(c.params[1].second, "100");
  EXPECT_EQ(c.params[2].second, "0.9");
  EXPECT_EQ(c.params[3].second, "20");
  EXPECT_EQ(c.params[4].second, std::to_string(monteCarloSeed(5, 1)));
  // Seeds: distinct, in the scenario's range, reproducible from the master seed.
  std::set<std::string> seeds;
  for (int i = 0; i < 3; ++i) seeds.insert(sw.cases[static_cast<size_t>(i)].params[4].second);
  EXPECT_EQ(seeds.size(), 3u);
  for (uint64_t i = 0; i < 1000; ++i) EXPECT_LE(monteCarloSeed(5, i), 0x7FFFFFFFull);
  EXPECT_NE(monteCarloSeed(5, 0), monteCarloSeed(6, 0));
}

TEST(Sweep, ErrorsNameTheLine) {
  Scratch sc;
  EXPECT_NE(sweepError(sc, "base: base.yaml\n").find("at least one of grid, zip or monte_carlo"), std::string::npos);
  EXPECT_NE(sweepError(sc, "base: nope.yaml\ngrid: {seed: [1]}\n").find("not found"), std::string::npos);
  const std::string zip = sweepError(sc, "base: base.yaml\nzip:\n  pack.initial_soc: [0.9, 0.8]\n  seed: [1, 2, 3]\n");
  EXPECT_NE(zip.find(":4:"), std::string::npos) << zip;
  EXPECT_NE(zip.find("has 3 values"), std::string::npos) << zip;
  EXPECT_NE(sweepError(sc, "base: base.yaml\ngrid: {seed: [1]}\nmonte_carlo: {samples: 2}\n").find("seed"),
            std::string::npos);
  EXPECT_NE(sweepError(sc, "base: base.yaml\ngrid: {seed: [1]}\nzip: {seed: [2]}\n").find("varied twice"),
            std::string::npos);
  EXPECT_NE(sweepError(sc, "base: base.yaml\ngird: {seed: [1]}\n").find("grid"), std::string::npos);
  EXPECT_NE(sweepError(sc, "base: base.yaml\ngrid: {seed: 1}\n").find("list"), std::string::npos);
  EXPECT_NE(sweepError(sc, "base: base.yaml\nmonte_carlo: {samples: 0}\n").find("samples"), std::string::npos);
}

TEST(Batch, RunsEveryCaseWritesCsvAndResumes) {
  Scratch sc;
  Sweep sw = loadSweepFile(sc.write("sweep.yaml",
                                    "base: base.yaml\noutput_dir: out\nthreads: 2\n"
                                    "grid:\n  pack.cell.capacity_Ah: [1.5, 2.0]\n  run.solver: [cvode, fast]\n"));
  BatchOptions opt;
  opt.progress = nullptr;
  const BatchReport r = runBatch(sw, opt);
  EXPECT_EQ(r.total, 4);
  EXPECT_EQ(r.ok, 4);
  EXPECT_EQ(r.failed, 0);
  EXPECT_EQ(r.skipped, 0);
  for (const SweepCase& c : sw.cases) EXPECT_TRUE(fs::exists(sw.resultPath(c))) << c.id;
  const std::vector<std::string> csv = lines(readFile(r.csv_path));
  ASSERT_EQ(csv.size(), 5u);
  EXPECT_EQ(csv[0].rfind("case,pack.cell.capacity_Ah,run.solver,status,", 0), 0u) << csv[0];
  EXPECT_NE(csv[0].find("energy_delivered_Wh"), std::string::npos);
  EXPECT_NE(csv[0].find(",error,file"), std::string::npos);
  EXPECT_EQ(csv[2].rfind("0001,1.5,fast,ok,", 0), 0u) << csv[2];
  // A smaller capacity ends at a lower SOC: the parameter reached the run.
  EXPECT_LT(std::stod(field(r.cases[0], "final_soc_min")), std::stod(field(r.cases[2], "final_soc_min")));
  // Both solvers ran the same case and agree.
  EXPECT_NEAR(std::stod(field(r.cases[0], "final_soc_min")), std::stod(field(r.cases[1], "final_soc_min")), 1e-6);

  // Rerun: every result is complete and holds the same scenario, so nothing runs.
  const BatchReport again = runBatch(sw, opt);
  EXPECT_EQ(again.skipped, 4);
  EXPECT_EQ(again.ok, 4);
  EXPECT_EQ(lines(readFile(again.csv_path)), csv);

  // A result of a different scenario (the sweep changed) is stale and runs again;
  // a missing one runs again.
  fs::remove(sw.resultPath(sw.cases[3]));
  Sweep changed = loadSweepFile(sc.write("sweep.yaml",
                                         "base: base.yaml\noutput_dir: out\n"
                                         "grid:\n  pack.cell.capacity_Ah: [1.5, 2.5]\n  run.solver: [cvode, fast]\n"));
  const BatchReport third = runBatch(changed, opt);
  EXPECT_EQ(third.skipped, 2);  // cases 0 and 1 are unchanged
  EXPECT_EQ(third.ok, 4);
}

// A base that extends another scenario stores the merged text; the resume check compared
// the base's own text with it, so such a batch never resumed (every case ran again).
TEST(Batch, ABaseThatExtendsAnotherResumes) {
  Scratch sc;
  sc.write("child.yaml", "extends: base.yaml\nname: child\n");
  Sweep sw = loadSweepFile(sc.write("sweep.yaml", "base: child.yaml\noutput_dir: out\ngrid:\n  load.current_A: [2, 3]\n"));
  BatchOptions opt;
  opt.progress = nullptr;
  EXPECT_EQ(runBatch(sw, opt).ok, 2);
  const BatchReport again = runBatch(sw, opt);
  EXPECT_EQ(again.skipped, 2);
  EXPECT_EQ(again.ok, 2);
}

// The scenario text names its load CSV; the CSV's content is not in it. Edited after the
// results were written, a resumed batch took them as done and reported the old run's
// summary. Now a result older than a file the case reads -- the load CSV, a file of the
// extends: chain, a CSV a grid names -- runs again.
TEST(Batch, AResultOlderThanTheLoadCsvRunsAgain) {
  Scratch sc;
  sc.write("lap.csv", "time_s,current_A\n0,1\n20,1\n");
  sc.write("other.csv", "time_s,current_A\n0,1\n20,1\n");
  sc.write("csvbase.yaml", test::simpleCellYaml(4) + "load: {csv: lap.csv}\nrun: {duration_s: 20}\n");
  Sweep sw = loadSweepFile(sc.write("sweep.yaml", "base: csvbase.yaml\noutput_dir: out\n"
                                                  "grid:\n  pack.cell.capacity_Ah: [1.5]\n"));
  Sweep byGrid = loadSweepFile(sc.write("sweep2.yaml", "base: csvbase.yaml\noutput_dir: out2\n"
                                                       "grid:\n  load.csv: [other.csv]\n"));
  BatchOptions opt;
  opt.progress = nullptr;
  const BatchReport first = runBatch(sw, opt);
  ASSERT_EQ(first.ok, 1);
  ASSERT_EQ(runBatch(byGrid, opt).ok, 1);
  const double charge1 = std::stod(field(first.cases[0], "charge_delivered_Ah"));
  EXPECT_EQ(runBatch(sw, opt).skipped, 1);  // nothing changed
  EXPECT_EQ(runBatch(byGrid, opt).skipped, 1);

  // The load doubles; the files are marked as changed after the results were written.
  const auto later = fs::last_write_time(sw.resultPath(sw.cases[0])) + std::chrono::seconds(2);
  sc.write("lap.csv", "time_s,current_A\n0,2\n20,2\n");
  fs::last_write_time(sc.dir / "lap.csv", later);
  const BatchReport again = runBatch(sw, opt);
  EXPECT_EQ(again.skipped, 0);
  ASSERT_EQ(again.ok, 1);
  EXPECT_NEAR(std::stod(field(again.cases[0], "charge_delivered_Ah")), 2 * charge1, 1e-6 + 1e-3 * charge1);

  sc.write("other.csv", "time_s,current_A\n0,2\n20,2\n");
  fs::last_write_time(sc.dir / "other.csv", later);
  EXPECT_EQ(runBatch(byGrid, opt).skipped, 0);
}

// A cell preset beside the base (cells/NAME.yaml), a route CSV and an irradiance CSV are
// read by the load but were not among the files a resumed batch compared with the result:
// an edited preset kept the old result. Now the case's files are the loader's own list
// (Scenario::files_read): the preset with its capacity doubled runs again, and the charge
// 3 A over 20 s (0.0167 Ah) now takes half the SOC from each cell.
TEST(Batch, AResultOlderThanACellPresetRouteOrIrradianceFileRunsAgain) {
  Scratch sc;
  fs::create_directories(sc.dir / "cells");
  const std::string cell = "ocv_V: {poly: [0.8, 3.4]}\nr0_ohm: 0.02\nrc_pairs: [{r_ohm: 0.01, c_F: 1000}]\n"
                           "heat_capacity_J_per_K: 40\ng_ambient_W_per_K: 0.1\n";
  sc.write("cells/mine.yaml", "capacity_Ah: 2.0\n" + cell);
  std::string base = test::simpleCellYaml(4);
  const size_t at = base.find("  cell:\n");
  base = base.substr(0, at) + "  cell: {preset: mine}\nhardware:" + base.substr(base.find("hardware:") + 9);
  sc.write("presetbase.yaml", base + "load: {current_A: 3}\nrun: {duration_s: 20}\n");
  Sweep sw = loadSweepFile(sc.write("sweep.yaml", "base: presetbase.yaml\noutput_dir: out\n"
                                                  "grid:\n  pack.initial_soc: [0.8]\n"));
  BatchOptions opt;
  opt.progress = nullptr;
  const BatchReport first = runBatch(sw, opt);
  ASSERT_EQ(first.ok, 1) << first.cases[0].error;
  EXPECT_EQ(runBatch(sw, opt).skipped, 1);  // nothing changed
  const double drop1 = 0.8 - std::stod(field(first.cases[0], "final_soc_min"));
  EXPECT_NEAR(drop1, 3.0 * 20.0 / 3600.0 / 2.0, 0.01 * drop1);  // 3 A for 20 s from 2 Ah

  const auto later = fs::last_write_time(sw.resultPath(sw.cases[0])) + std::chrono::seconds(2);
  sc.write("cells/mine.yaml", "capacity_Ah: 4.0\n" + cell);
  fs::last_write_time(sc.dir / "cells/mine.yaml", later);
  const BatchReport again = runBatch(sw, opt);
  EXPECT_EQ(again.skipped, 0);
  ASSERT_EQ(again.ok, 1);
  EXPECT_NEAR(0.8 - std::stod(field(again.cases[0], "final_soc_min")), drop1 / 2.0, 0.01 * drop1);

  // A route and an irradiance table (a vehicle base, not run here): both among the files.
  sc.write("circuit.csv", "distance_km,grade_percent,speed_kmh\n0,0,27\n1.6,0,27\n");
  sc.write("sun.csv", "time_s,ghi_W_per_m2\n0,200\n3000,300\n");
  const std::string car = sc.write(
      "car.yaml", "extends: " + test::scenarioDir() + "/vehicle/eco_marathon_12s_circuit.yaml\n"
                  "load:\n  route: {csv: circuit.csv, segments: [], laps: 1}\n"
                  "  sun: {array_area_m2: 0.5, efficiency: 0.2, mppt_efficiency: 0.95, start_solar_hour: 10, "
                  "irradiance_csv: sun.csv}\nexpect: {}\n");
  Sweep cars = loadSweepFile(sc.write("cars.yaml", "base: car.yaml\noutput_dir: cars\ngrid:\n  pack.initial_soc: [0.9]\n"));
  const Scenario s = loadScenarioWithOverrides(cars.base_text, cars.cases[0].params, "case", sc.dir.string());
  const std::vector<std::string> files = caseInputFiles(cars, s);
  for (const char* name : {"circuit.csv", "sun.csv", "car.yaml"}) {
    bool listed = false;
    for (const std::string& f : files) listed = listed || fs::equivalent(f, sc.dir / name);
    EXPECT_TRUE(listed) << name;
  }
}

// summary.csv is written under a temporary name of this process (uniqueTemporaryName),
// not a fixed `summary.csv.tmp` that two batches into one folder would share: a folder
// already holding that name (here a directory, which no file write can replace) does not
// stop the batch from writing its table.
TEST(Batch, SummaryTableHasATemporaryOfItsOwn) {
  Scratch sc;
  Sweep sw = loadSweepFile(sc.write("sweep.yaml", "base: base.yaml\noutput_dir: out\ngrid:\n  pack.initial_soc: [0.9]\n"));
  fs::create_directories(sc.dir / "out" / "summary.csv.tmp");
  BatchOptions opt;
  opt.progress = nullptr;
  const BatchReport r = runBatch(sw, opt);
  EXPECT_EQ(r.ok, 1);
  EXPECT_EQ(lines(readFile(r.csv_path)).size(), 2u);
  for (const auto& e : fs::directory_iterator(sc.dir / "out"))
    EXPECT_EQ(e.path().filename().string().find("summary.csv.tmp."), std::string::npos) << "left behind: " << e.path();
}

TEST(Batch, FailingCaseIsRecordedAndOthersFinish) {
  Scratch sc;
  // Each value is valid on the base, but the second pair is not (v_max_V 3.5 below
  // v_min_V 3.9): that case fails at load, the other two run.
  Sweep sw = loadSweepFile(sc.write("sweep.yaml", "base: base.yaml\noutput_dir: out\n"
                                                  "zip: {pack.cell.v_min_V: [2.8, 3.9, 2.7], pack.cell.v_max_V: [4.3, 3.5, 4.4]}\n"));
  BatchOptions opt;
  opt.progress = nullptr;
  const BatchReport r = runBatch(sw, opt);
  EXPECT_EQ(r.ok, 2);
  EXPECT_EQ(r.failed, 1);
  EXPECT_FALSE(r.cases[1].ok);
  EXPECT_NE(r.cases[1].error.find("v_max_V"), std::string::npos) << r.cases[1].error;
  EXPECT_FALSE(fs::exists(sw.resultPath(sw.cases[1])));
  const std::vector<std::string> csv = lines(readFile(r.csv_path));
  ASSERT_EQ(csv.size(), 4u);
  EXPECT_EQ(csv[2].rfind("0001,3.9,3.5,failed,", 0), 0u) << csv[2];
  EXPECT_NE(csv[2].find("v_max_V"), std::string::npos);
  EXPECT_EQ(csv[3].rfind("0002,2.7,4.4,ok,", 0), 0u) << csv[3];
}

// A varied value the base scenario refuses on its own (out of range) is the sweep's
// error at the value's line and column, before any case runs (docs/batch.md).
TEST(Batch, AValueOutOfRangeIsTheSweepsErrorAtItsLine) {
  Scratch sc;
  const std::string path = sc.write("sweep.yaml", "base: base.yaml\noutput_dir: out\n"
                                                  "grid:\n  pack.initial_soc: [0.8, 1.5, 0.6]\n");
  try {
    loadSweepFile(path);
    FAIL() << "expected a ScenarioError";
  } catch (const ScenarioError& e) {
    EXPECT_EQ(e.line(), 4);
    EXPECT_EQ(e.column(), 27);
    EXPECT_EQ(e.field(), "grid.pack.initial_soc");
    EXPECT_NE(e.message().find("1.5 is out of range; allowed [0, 1]"), std::string::npos) << e.message();
  }
  EXPECT_FALSE(fs::exists(sc.dir / "out"));
}

TEST(Batch, CliExitStatusSaysSomeFailed) {
  Scratch sc;
  const std::string ok = sc.write("ok.yaml", "base: base.yaml\noutput_dir: out_ok\nmonte_carlo: {samples: 2}\n");
  const std::string bad = sc.write("bad.yaml", "base: base.yaml\noutput_dir: out_bad\n"
                                               "zip: {pack.cell.v_min_V: [2.8, 3.9], pack.cell.v_max_V: [4.3, 3.5]}\n");
  const std::string range = sc.write("range.yaml", "base: base.yaml\noutput_dir: out_range\n"
                                                   "grid: {pack.initial_soc: [0.8, 1.5]}\n");
  const std::string typo = sc.write("typo.yaml", "base: base.yaml\noutput_dir: out_typo\n"
                                                 "grid: {pack.cell.capacty_Ah: [1, 2]}\n");
  auto run = [](const std::string& args) {
    const int rc = std::system((std::string(PACKSIM_BINARY) + " batch -q " + args + " 2>/dev/null").c_str());
    return WEXITSTATUS(rc);
  };
  EXPECT_EQ(run(ok), 0);
  EXPECT_TRUE(fs::exists(sc.dir / "out_ok" / "summary.csv"));
  EXPECT_EQ(run(bad), 1);
  EXPECT_EQ(run(typo), 2);  // checked before anything runs
  EXPECT_FALSE(fs::exists(sc.dir / "out_typo"));
  EXPECT_EQ(run(range), 2);  // so is a value out of range
  EXPECT_FALSE(fs::exists(sc.dir / "out_range"));
}

// A Monte Carlo records each case's drawn cell values (core/batch/drawn_inputs.hpp): in
// summary.csv and the result file, the same for the same seed, different between samples,
// constant for a spread that is not drawn -- and the values the run used: with 3 A for
// 20 s and no self-discharge, the lowest final SOC is 0.8 - (the charge delivered) / the smallest drawn
// capacity, an independent account of the charge.
TEST(Batch, MonteCarloRecordsTheDrawnInputs) {
  Scratch sc;
  std::string base = test::simpleCellYaml(4);
  base.insert(base.find("  cell:"), "  spread: {capacity_rel_sd: 0.05}\n");
  std::ofstream(sc.dir / "spread.yaml") << base << "load: {current_A: 3}\nrun: {duration_s: 20, solver: fast}\n";
  const std::string text = "base: spread.yaml\nmonte_carlo: {samples: 4, master_seed: 11}\n";
  Sweep a = loadSweepText(text + "output_dir: a\n", "", sc.dir.string());
  Sweep b = loadSweepText(text + "output_dir: b\n", "", sc.dir.string());
  BatchOptions opt;
  opt.progress = nullptr;
  const BatchReport ra = runBatch(a, opt), rb = runBatch(b, opt);
  ASSERT_EQ(ra.ok, 4) << ra.cases[0].error;
  ASSERT_EQ(rb.ok, 4);
  std::set<std::string> capacities;
  for (size_t i = 0; i < ra.cases.size(); ++i) {
    const CaseOutcome& o = ra.cases[i];
    for (const char* name : {"drawn_capacity_min_Ah", "drawn_capacity_max_Ah", "drawn_charge_min_Ah",
                             "drawn_r0_scale_max", "drawn_initial_soc_min", "drawn_weakest_group"})
      EXPECT_EQ(field(o, name), field(rb.cases[i], name)) << name << " of case " << i;  // same seed, same draw
    capacities.insert(field(o, "drawn_capacity_min_Ah"));
    const double cmin = std::stod(field(o, "drawn_capacity_min_Ah"));
    EXPECT_LT(cmin, std::stod(field(o, "drawn_capacity_max_Ah")));
    EXPECT_GT(cmin, 2.0 * (1 - 3 * 0.05) - 1e-12);  // truncated at 3 sd
    EXPECT_NEAR(std::stod(field(o, "drawn_charge_min_Ah")), 0.8 * cmin, 1e-9);
    EXPECT_EQ(field(o, "drawn_r0_scale_max"), "1");  // not drawn
    EXPECT_EQ(field(o, "drawn_r0_scale_rel_sd"), "0");
    EXPECT_EQ(field(o, "drawn_initial_soc_min"), "0.8");
    const double q = std::stod(field(o, "charge_delivered_Ah"));  // through every cell of the string
    EXPECT_NEAR(q, 3.0 * 20.0 / 3600.0, 1e-4);
    EXPECT_NEAR(std::stod(field(o, "final_soc_min")), 0.8 - q / cmin, 1e-8) << "case " << i;
  }
  EXPECT_EQ(capacities.size(), 4u);  // each sample its own draw
  const std::vector<std::string> csv = lines(readFile(ra.csv_path));
  EXPECT_EQ(csv[0].rfind("case,seed,status,drawn_capacity_min_Ah,drawn_capacity_max_Ah,", 0), 0u) << csv[0];
  // The per-cell values are in the result file, under /inputs.
  const std::string h5 = readFile(a.resultPath(a.cases[0]));
  EXPECT_NE(h5.find("cell_capacity_Ah"), std::string::npos);
}

// A pack without a spread: every group's capacity is the same, and its spread is 0, not
// the 3e-16 an ulp off the summed mean of 13 groups of 4 x 3.1 Ah made of it.
TEST(Batch, APackWithoutASpreadHasASpreadOfExactlyZero) {
  const Scenario s = test::scenarioFromYaml(
      "name: p\npack: {series: 13, parallel: 4, cell: {preset: ncr18650_3p1Ah}}\nload: {current_A: 1}\n"
      "run: {duration_s: 1}\n");
  for (const auto& [name, value] : drawnInputFigures(drawnInputs(s)))
    if (name == "drawn_capacity_rel_sd" || name == "drawn_r0_scale_rel_sd") EXPECT_EQ(value, 0.0) << name;
}

TEST(Batch, CsvFieldQuoting) {
  EXPECT_EQ(csvField("plain"), "plain");
  EXPECT_EQ(csvField("a,b"), "\"a,b\"");
  EXPECT_EQ(csvField("say \"hi\""), "\"say \"\"hi\"\"\"");
  EXPECT_EQ(csvField("two\nlines"), "\"two\nlines\"");
}

}  // namespace
}  // namespace packsim
