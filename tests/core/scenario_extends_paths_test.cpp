// A base's files are its own folder's, wherever the scenario extending it sits: its cell
// preset (cells/NAME.yaml next to the base), its firmware library and config_file (paths
// with a folder), as its CSV load always was (core/scenario/load_scenario.cpp).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "core/scenario/load_scenario.hpp"
#include "test_support.hpp"

namespace packsim {
namespace {

namespace fs = std::filesystem;

void write(const fs::path& p, const std::string& text) {
  fs::create_directories(p.parent_path());
  std::ofstream(p) << text;
}

TEST(ExtendsPaths, ABasesOwnPresetIsFoundFromAChildElsewhere) {
  const fs::path d = test::freshTempDir("packsim_extends_paths_", "preset");
  // The base's own cell: 7 Ah, OCV flat 3.3 V (no bundled preset is).
  write(d / "lib" / "cells" / "team_cell.yaml", "capacity_Ah: 7\nocv_V: 3.3\nr0_ohm: 0.004\n");
  write(d / "lib" / "base.yaml", "pack: {series: 3, cell: {preset: team_cell}}\nload: {current_A: 1}\nrun: {duration_s: 10}\n");
  write(d / "work" / "deep" / "child.yaml", "extends: ../../lib/base.yaml\nseed: 4\n");
  // Was: "pack.cell.preset: unknown cell preset 'team_cell' (available: lipo_5Ah, ...)".
  const fs::path child = d / "work" / "deep" / "child.yaml";
  Scenario s;
  ASSERT_NO_THROW(s = loadScenarioFile(child.string())) << test::fileErrorOf(child);
  EXPECT_DOUBLE_EQ(s.pack.cell.capacity_Ah, 7.0);
  // A child that names a preset itself looks it up from its own folder.
  write(d / "work" / "deep" / "cells" / "team_cell.yaml", "capacity_Ah: 9\nocv_V: 3.3\nr0_ohm: 0.004\n");
  write(d / "work" / "deep" / "own.yaml", "extends: ../../lib/base.yaml\npack: {cell: {preset: team_cell}}\n");
  EXPECT_DOUBLE_EQ(loadScenarioFile((d / "work" / "deep" / "own.yaml").string()).pack.cell.capacity_Ah, 9.0);
  // The base's own preset still stands over a same-named one next to a child that does not name it.
  EXPECT_DOUBLE_EQ(loadScenarioFile(child.string()).pack.cell.capacity_Ah, 7.0);
}

TEST(ExtendsPaths, ABasesFirmwareFilesAreItsFoldersFiles) {
  const fs::path d = test::freshTempDir("packsim_extends_paths_", "firmware");
  write(d / "lib" / "fw" / "libteam_bms.so", "not loaded at load time");
  write(d / "lib" / "fw" / "team.cfg", "ABCD");
  write(d / "lib" / "base.yaml", test::simpleCellYaml() +
                                     "bms: {firmware: {library: fw/libteam_bms.so, config_file: fw/team.cfg}}\n"
                                     "load: {current_A: 1}\nrun: {duration_s: 10}\n");
  write(d / "work" / "child.yaml", "extends: ../lib/base.yaml\nseed: 4\n");
  // Was: "bms.firmware.library: ... not found" (looked for work/fw/libteam_bms.so).
  const fs::path child = d / "work" / "child.yaml";
  Scenario s;
  ASSERT_NO_THROW(s = loadScenarioFile(child.string())) << test::fileErrorOf(child);
  EXPECT_EQ(fs::weakly_canonical(s.bms.firmware.library_path), fs::weakly_canonical(d / "lib" / "fw" / "libteam_bms.so"));
  EXPECT_EQ(s.bms.firmware.config, (std::vector<uint8_t>{'A', 'B', 'C', 'D'}));
}

TEST(ExtendsPaths, AChildChangesTheInheritedCsvMappingOrGivesANewLog) {
  const fs::path d = test::freshTempDir("packsim_extends_paths_", "csv");
  write(d / "lib" / "logs" / "drive.csv", "t,amps\n0,-5\n10,-8\n20,-2\n");
  write(d / "lib" / "base.yaml", test::simpleCellYaml() +
                                     "load: {csv: {file: logs/drive.csv, time_column: t, current_column: amps}}\n");
  // The logger counts discharge negative: the child flips the inherited log's sign.
  // Was: "load.csv: missing required key 'file' (given: scale)".
  write(d / "work" / "flip.yaml", "extends: ../lib/base.yaml\nload: {csv: {scale: -1}}\n");
  const fs::path flip = d / "work" / "flip.yaml";
  Scenario s;
  ASSERT_NO_THROW(s = loadScenarioFile(flip.string())) << test::fileErrorOf(flip);
  EXPECT_EQ(s.load.i_A, (std::vector<double>{5, 8, 2}));
  // A child's own log is read as written: the base's column names do not carry over.
  write(d / "work" / "own.csv", "time_s,current_A\n0,1\n10,1\n");
  write(d / "work" / "own.yaml", "extends: ../lib/base.yaml\nload: {csv: {file: own.csv}}\n");
  EXPECT_EQ(loadScenarioFile((d / "work" / "own.yaml").string()).load.i_A, (std::vector<double>{1, 1}));
}

}  // namespace
}  // namespace packsim
