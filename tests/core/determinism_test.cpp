// Same scenario + same seed -> bit-identical HDF5 datasets; another seed changes
// what the BMS measured (noise) but not the plant's truth before any decision differs.
#include <gtest/gtest.h>

#include <filesystem>

#include "core/io/hdf5_writer.hpp"
#include "core/sim/simulation.hpp"
#include "test_support.hpp"

namespace packsim {
namespace {

namespace fs = std::filesystem;

TEST(Determinism, SameSeedGivesBitIdenticalDatasets) {
  const fs::path dir = test::processTempDir("packsim_determinism");
  fs::create_directories(dir);
  const Scenario s = loadScenarioFile(test::scenarioDir() + "/eco_marathon_12s.yaml");
  const std::string a = (dir / "a.h5").string(), b = (dir / "b.h5").string(), c = (dir / "c.h5").string();
  writeResultHdf5(a, s, runScenario(s));
  writeResultHdf5(b, s, runScenario(s));
  Scenario other = s;
  other.run.seed = s.run.seed + 1;
  writeResultHdf5(c, other, runScenario(other));
  for (const char* ds : {"/time_s", "/truth/cell_voltage_V", "/truth/cell_soc", "/truth/cell_temp_C",
                         "/truth/pack_current_A", "/measured/cell_voltage_mV", "/measured/temperature_dC",
                         "/measured/current_mA", "/bms/state", "/bms/fault_latched", "/bms/relay_closed"}) {
    const auto da = test::readDatasetBytes(a, ds);
    ASSERT_FALSE(da.empty()) << ds;
    EXPECT_EQ(da, test::readDatasetBytes(b, ds)) << ds;
  }
  EXPECT_NE(test::readDatasetBytes(a, "/measured/cell_voltage_mV"), test::readDatasetBytes(c, "/measured/cell_voltage_mV"));
  // Whole files too: no timestamps inside.
  EXPECT_EQ(fs::file_size(a), fs::file_size(b));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace packsim
