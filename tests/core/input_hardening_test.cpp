// Hardening of the input paths (issue 16): extends cycles, repeated YAML keys, a typo
// under a cell preset, and command-line argument errors (exit 2, one short line, the
// closest valid name).
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/batch/sweep.hpp"
#include "core/sim/simulation.hpp"
#include "test_support.hpp"

namespace packsim {
namespace {

namespace fs = std::filesystem;

fs::path freshDir(const std::string& name) { return test::freshTempDir("packsim_hardening_", name); }

void write(const fs::path& p, const std::string& text) { std::ofstream(p) << text; }

std::string loadError(const fs::path& file) { return test::fileErrorOf(file); }

std::string yamlError(const std::string& yaml) { return test::yamlErrorOf(yaml); }

const std::string& kLoad = test::kSimpleLoadYaml;

TEST(InputHardening, ExtendsItselfIsACycleNotACrash) {
  const fs::path d = freshDir("self");
  write(d / "a.yaml", "extends: a.yaml\nseed: 3\n");
  const std::string e = loadError(d / "a.yaml");
  EXPECT_NE(e.find("a.yaml:1:10: extends: extends cycle: a.yaml -> a.yaml"), std::string::npos) << e;
}

TEST(InputHardening, LongerExtendsCycleNamesTheChain) {
  const fs::path d = freshDir("cycle");
  write(d / "a.yaml", "extends: b.yaml\n");
  write(d / "b.yaml", "seed: 2\nextends: c.yaml\n");
  write(d / "c.yaml", "extends: a.yaml\n");
  const std::string e = loadError(d / "a.yaml");
  EXPECT_NE(e.find("c.yaml:1:10: extends: extends cycle: a.yaml -> b.yaml -> c.yaml -> a.yaml"), std::string::npos) << e;
}

TEST(InputHardening, DeepButAcyclicExtendsStillLoads) {
  const fs::path d = freshDir("chain");
  write(d / "base.yaml", test::simpleCellYaml() + kLoad);
  write(d / "mid.yaml", "extends: base.yaml\nseed: 5\n");
  write(d / "top.yaml", "extends: mid.yaml\nrun: {duration_s: 20}\n");
  const Scenario s = loadScenarioFile((d / "top.yaml").string());
  EXPECT_EQ(s.run.seed, 5u);
  EXPECT_EQ(s.run.duration_s, 20.0);
}

// issue 28: a scenario whose load is a CSV in its own folder (not a bundled one), in
// either form, extended from another folder and by a file holding nothing but the
// `extends:` line, runs bit for bit as the base itself (the CSV path stays relative to
// the base's folder). Before, the mapping form became the path "." ("./.: empty CSV").
void expectSameRun(const RunResult& a, const RunResult& b) {
  EXPECT_EQ(a.rec.time_s, b.rec.time_s);
  EXPECT_EQ(a.rec.cell_voltage_V, b.rec.cell_voltage_V);
  EXPECT_EQ(a.rec.cell_current_A, b.rec.cell_current_A);
  EXPECT_EQ(a.rec.cell_temp_C, b.rec.cell_temp_C);
  EXPECT_EQ(a.rec.cell_soc, b.rec.cell_soc);
  EXPECT_EQ(a.rec.meas_cell_voltage_mV, b.rec.meas_cell_voltage_mV);
  EXPECT_EQ(a.summary.heat_Wh, b.summary.heat_Wh);
  EXPECT_EQ(a.summary.charge_delivered_Ah, b.summary.charge_delivered_Ah);
  ASSERT_EQ(a.events.size(), b.events.size());
}

TEST(InputHardening, ExtendsOfAScenarioWithACsvLoadRunsAsTheBase) {
  const fs::path d = freshDir("extends_csv");
  fs::create_directories(d / "lib");
  fs::create_directories(d / "work" / "deeper");
  write(d / "lib" / "lap.csv", "t,I\n0,1.0\n3,2.5\n7.5,0.5\n12,3.0\n20,0\n");
  write(d / "lib" / "plain.csv", "time_s,current_A\n0,2.0\n5,1.0\n20,0\n");
  write(d / "lib" / "base.yaml", test::simpleCellYaml() +
                                     "load: {csv: {file: lap.csv, time_column: t, current_column: I}}\n"
                                     "run: {duration_s: 20}\n");
  write(d / "lib" / "base_plain.yaml", test::simpleCellYaml() + "load: {csv: plain.csv}\nrun: {duration_s: 20}\n");
  write(d / "lib" / "only_extends.yaml", "# the base, as it is\nextends: base.yaml\n");
  write(d / "work" / "deeper" / "child.yaml", "extends: ../../lib/base.yaml\nseed: 3\n");
  write(d / "work" / "child_plain.yaml", "extends: ../lib/base_plain.yaml\n");
  const RunResult base = runScenario(loadScenarioFile((d / "lib" / "base.yaml").string()));
  ASSERT_GT(base.rec.time_s.size(), 10u);
  for (const fs::path& f : {d / "lib" / "only_extends.yaml", d / "work" / "deeper" / "child.yaml"}) {
    SCOPED_TRACE(f.string());
    Scenario s;
    ASSERT_NO_THROW(s = loadScenarioFile(f.string())) << test::fileErrorOf(f);
    EXPECT_EQ(s.load.t_s, (std::vector<double>{0, 3, 7.5, 12, 20}));
    expectSameRun(runScenario(s), base);
  }
  const RunResult plain = runScenario(loadScenarioFile((d / "lib" / "base_plain.yaml").string()));
  Scenario s;
  const fs::path child = d / "work" / "child_plain.yaml";
  ASSERT_NO_THROW(s = loadScenarioFile(child.string())) << test::fileErrorOf(child);
  expectSameRun(runScenario(s), plain);
}

// `extends:` takes a bundled scenario's name as `packsim run NAME` does (found as a new
// user would write it: `extends: formula_student_96s` was "file not found"); a file next
// to the scenario comes first, and a name that is neither says so with the closest name.
TEST(InputHardening, ExtendsTakesABundledScenarioByName) {
  const fs::path d = freshDir("extends_bundled");
  const std::string bundled = bundledScenarioDir() + "/bench_6s_ncr18650_2C.yaml";
  write(d / "by_name.yaml", "extends: bench_6s_ncr18650_2C\nrun: {duration_s: 30}\n");
  write(d / "by_path.yaml", "extends: " + bundled + "\nrun: {duration_s: 30}\n");
  write(d / "by_folder.yaml", "extends: faults/a_estop\nrun: {duration_s: 30}\n");
  Scenario byName, byPath;
  ASSERT_NO_THROW(byName = loadScenarioFile((d / "by_name.yaml").string())) << loadError(d / "by_name.yaml");
  ASSERT_NO_THROW(byPath = loadScenarioFile((d / "by_path.yaml").string())) << loadError(d / "by_path.yaml");
  EXPECT_EQ(byName.pack.series, 6);
  EXPECT_EQ(byName.run.duration_s, 30.0);
  expectSameRun(runScenario(byName), runScenario(byPath));
  EXPECT_EQ(loadError(d / "by_folder.yaml"), "<no error>");

  write(d / "bench_6s_ncr18650_2C", "");  // a file of that name next to the scenario wins (empty: an error)
  EXPECT_NE(loadError(d / "by_name.yaml"), "<no error>");

  write(d / "typo.yaml", "extends: formula_student_69s\n");
  const std::string e = loadError(d / "typo.yaml");
  EXPECT_NE(e.find("typo.yaml:1:10: extends: file not found: "), std::string::npos) << e;
  EXPECT_NE(e.find("nor a bundled scenario of that name (did you mean 'formula_student_96s'?)"), std::string::npos) << e;
  write(d / "typo_file.yaml", "extends: formula_student_69s.yaml\n");  // a file name: no bundled lookup
  const std::string f = loadError(d / "typo_file.yaml");
  EXPECT_NE(f.find("file not found: "), std::string::npos) << f;
  EXPECT_EQ(f.find("nor a bundled scenario"), std::string::npos) << f;
  EXPECT_EQ(f.find("the bundled scenario of that name"), std::string::npos) << f;  // no such bundled one
  // A bundled scenario's file name from a folder of the user's own (as the test suite's
  // own scenarios write it, next to the bundled ones): not found, but the error says how.
  write(d / "with_ext.yaml", "extends: bench_6s_ncr18650_2C.yaml\n");
  const std::string g = loadError(d / "with_ext.yaml");
  EXPECT_NE(g.find("with_ext.yaml:1:10: extends: file not found: "), std::string::npos) << g;
  EXPECT_NE(g.find("; the bundled scenario of that name is `extends: bench_6s_ncr18650_2C` (no extension)"),
            std::string::npos)
      << g;
}

TEST(InputHardening, DuplicateKeyNamesBothPlaces) {
  const std::string e = yamlError("seed: 1\n" + test::simpleCellYaml() + kLoad + "seed: 2\n");
  EXPECT_NE(e.find(": seed: duplicate key (first given at line 1, column 1)"), std::string::npos) << e;
  EXPECT_NE(e.find("test.yaml:"), std::string::npos) << e;
}

TEST(InputHardening, NestedDuplicateKeyIsRefused) {
  std::string y = test::simpleCellYaml() + kLoad;
  y.replace(y.find("    capacity_Ah: 2.0\n"), 21, "    capacity_Ah: 2.0\n    capacity_Ah: 3.0\n");
  const std::string e = yamlError(y);
  EXPECT_NE(e.find("test.yaml:9:5: capacity_Ah: duplicate key (first given at line 8, column 5)"), std::string::npos) << e;
}

TEST(InputHardening, TypoUnderACellPresetKeepsItsLineAndColumn) {
  const std::string y =
      "pack:\n"
      "  series: 2\n"
      "  cell:\n"
      "    preset: ncr18650_3p1Ah\n"
      "    capcity_Ah: 3.0\n" +
      kLoad;
  const std::string e = yamlError(y);
  EXPECT_NE(e.find("test.yaml:5:5: pack.cell.capcity_Ah: unknown key; did you mean 'capacity_Ah'?"), std::string::npos)
      << e;
}

TEST(InputHardening, TypoInAScenarioThatExtendsAnotherKeepsItsLineAndColumn) {
  const fs::path d = freshDir("extends_typo");
  write(d / "base.yaml", test::simpleCellYaml() + kLoad);
  write(d / "child.yaml", "extends: base.yaml\npack:\n  cell:\n    preset: lipo_5Ah\n    capcity_Ah: 4\n");
  const std::string e = loadError(d / "child.yaml");
  EXPECT_NE(e.find("child.yaml:5:5: pack.cell.capcity_Ah: unknown key; did you mean 'capacity_Ah'?"), std::string::npos) << e;
  write(d / "child2.yaml", "extends: base.yaml\nrun: {duration_s: 10, rtoll: 1e-6}\n");
  const std::string e2 = loadError(d / "child2.yaml");
  EXPECT_NE(e2.find("child2.yaml:2:23: run.rtoll: unknown key; did you mean 'rtol'?"), std::string::npos) << e2;
}

// A base valid alone, made invalid by its child: the error sits on the base's line, so it
// names the base's file (it named the child's file with the base's line).
TEST(InputHardening, AnErrorOnABaseKeyAfterMergingNamesTheBaseFile) {
  const fs::path d = freshDir("extends_base_line");
  write(d / "base.yaml", "name: base\npack:\n  series: 40\n  cell: {preset: lipo_5Ah}\nload: {current_A: 2}\n"
                         "run: {duration_s: 10}\nhardware:\n  thermistors: {at_groups: [30]}\n");
  write(d / "child.yaml", "extends: base.yaml\nname: child\npack: {series: 20}\n");
  const std::string e = loadError(d / "child.yaml");
  EXPECT_NE(e.find("base.yaml:8:29: hardware.thermistors.at_groups[0]: 30 is out of range; allowed [1, 20]"),
            std::string::npos) << e;
  EXPECT_GT(e.find("child.yaml"), e.find("(the value comes from ")) << e;  // the location is the base's
  EXPECT_NE(e.find(" (the value comes from base.yaml; give hardware.thermistors.at_groups in child.yaml to replace it)"),
            std::string::npos) << e;
  // The child's own keys still name the child.
  write(d / "child2.yaml", "extends: base.yaml\nname: child\npack: {series: 40, initial_soc: 2}\n");
  const std::string e2 = loadError(d / "child2.yaml");
  EXPECT_NE(e2.find("child2.yaml:3:"), std::string::npos) << e2;
}

TEST(InputHardening, OverrideUnderACellPresetKeepsItsValueLine) {
  const std::string y = "pack:\n  series: 2\n  cell:\n    preset: ncr18650_3p1Ah\n    capacity_Ah: -3\n" + kLoad;
  const std::string e = yamlError(y);
  EXPECT_NE(e.find("test.yaml:5:18: pack.cell.capacity_Ah: -3 is out of range"), std::string::npos) << e;
}

struct CliResult {
  int status;
  std::string err;
};

CliResult runCli(const std::string& args) {
  // One file per test: ctest runs the tests of this binary in parallel processes.
  const fs::path errFile = test::processTempDir("packsim_hardening") /
                           ("cli_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) + ".err");
  const int rc = std::system((std::string(PACKSIM_BINARY) + " " + args + " >/dev/null 2>" + errFile.string()).c_str());
  std::ifstream in(errFile);
  std::stringstream ss;
  ss << in.rdbuf();
  return {WIFEXITED(rc) ? WEXITSTATUS(rc) : -1, ss.str()};
}

size_t lines(const std::string& s) { return static_cast<size_t>(std::count(s.begin(), s.end(), '\n')); }

TEST(CliErrors, MistypedSubcommandSuggestsTheClosest) {
  const CliResult r = runCli("rn");
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(lines(r.err), 1u) << r.err;
  EXPECT_NE(r.err.find("unknown command 'rn'; did you mean 'run'?"), std::string::npos) << r.err;
}

TEST(CliErrors, MistypedOptionSuggestsTheClosest) {
  const CliResult r = runCli("run --seeed 3");  // (--sed is as close to --set as to --seed)
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(lines(r.err), 1u) << r.err;
  EXPECT_NE(r.err.find("packsim run: error: unknown option '--seeed'; did you mean '--seed'?"), std::string::npos) << r.err;
}

// A seed is a scenario's `seed:`, [0, 2147483647]: one short line for what is not, never a
// wrapped value (18446744073709551616 ran as seed 2^64 - 1, stored as -1, exit 0).
TEST(CliErrors, ASeedOutsideTheScenarioRangeIsOneShortLine) {
  for (const char* seed : {"-1", "2147483648", "18446744073709551616", "1.5"}) {
    const CliResult r = runCli(std::string("run --seed ") + seed);
    EXPECT_EQ(r.status, 2) << seed;
    EXPECT_EQ(lines(r.err), 1u) << r.err;
    EXPECT_NE(r.err.find(std::string("--seed: expected a whole number in [0, 2147483647] (a scenario's seed: range), got ") +
                         seed),
              std::string::npos)
        << r.err;
    EXPECT_LT(r.err.size(), 160u) << r.err;
  }
}

TEST(CliErrors, EveryArgumentErrorExitsTwo) {
  for (const char* args : {"", "run --seed abc", "batch", "plot", "check --bogus", "batch s.yaml -j 0",
                           "balance-time --resistor x", "plot r.h5 --dpi -3"}) {
    const CliResult r = runCli(args);
    EXPECT_EQ(r.status, 2) << args << ": " << r.err;
    EXPECT_EQ(lines(r.err), 1u) << args << ": " << r.err;
    EXPECT_LT(r.err.size(), 200u) << args << ": " << r.err;
  }
}

TEST(CliErrors, HelpAndVersionStillExitZero) {
  EXPECT_EQ(runCli("--help").status, 0);
  EXPECT_EQ(runCli("run --help").status, 0);
  EXPECT_EQ(runCli("--version").status, 0);
}

}  // namespace
}  // namespace packsim

namespace packsim {
namespace {

// Found by fuzzing (tests/fuzz/regressions/fuzz_scenario/extends_name_too_long): a file
// name longer than the file system allows made std::filesystem throw past the loader.
TEST(FuzzRegressions, OverlongFileNamesAreNotFoundErrors) {
  const std::string longName(300, 'x');
  const fs::path d = freshDir("long_names");
  write(d / "a.yaml", "extends: " + longName + ".yaml\n");
  EXPECT_NE(loadError(d / "a.yaml").find("a.yaml:1:10: extends: file not found"), std::string::npos);
  std::string y = test::simpleCellYaml() + "load: {csv: " + longName + ".csv}\n";
  EXPECT_NE(yamlError(y).find("load.csv: file not found"), std::string::npos) << yamlError(y);
  y = "pack:\n  series: 1\n  cell: {preset: " + longName + "}\n" + kLoad;
  EXPECT_NE(yamlError(y).find("unknown cell preset"), std::string::npos) << yamlError(y);
  // A preset given as a file name (as `packsim fit -o` writes it) is told how presets are found.
  y = "pack:\n  series: 1\n  cell: {preset: my_cell.yaml}\n" + kLoad;
  EXPECT_NE(yamlError(y).find("a preset is named without '.yaml' and found as cells/my_cell.yaml next to the scenario"),
            std::string::npos)
      << yamlError(y);
  write(d / "sweep.yaml", "base: " + longName + ".yaml\ngrid: {seed: [1, 2]}\n");
  try {
    loadSweepFile((d / "sweep.yaml").string());
    ADD_FAILURE() << "no error";
  } catch (const ScenarioError& e) {
    EXPECT_NE(std::string(e.what()).find("base: scenario file not found"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace packsim
