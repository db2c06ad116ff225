// The result-channel table against what a run records and what the writer writes: each
// channel a run holds has samples × axis values and is written bit for bit under its
// path with its unit; a channel the run does not hold is neither recorded nor written.
#include "core/sim/result_channels.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <hdf5.h>

#include <cstring>
#include <filesystem>
#include <sstream>
#include <set>
#include <variant>

#include "core/io/hdf5_writer.hpp"
#include "core/scenario/overrides.hpp"
#include "core/sim/simulation.hpp"
#include "test_support.hpp"

namespace packsim {
namespace {

namespace fs = std::filesystem;

struct Run {
  Scenario s;
  RunResult r;
};

Run runBundled(const std::string& name) {
  Run run;
  run.s = loadScenarioFileWithOverrides(test::scenarioDir() + "/" + name, {{"run.duration_s", "4"}});
  run.r = runScenario(run.s);
  return run;
}

std::string unitsOf(const std::string& file, const std::string& path) {
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  const hid_t d = H5Dopen2(f, path.c_str(), H5P_DEFAULT);
  std::string units;
  if (H5Aexists(d, "units") > 0) {
    const hid_t a = H5Aopen(d, "units", H5P_DEFAULT);
    const hid_t t = H5Aget_type(a);
    units.resize(H5Tget_size(t));
    H5Aread(a, t, units.data());
    units.resize(std::strlen(units.c_str()));
    H5Tclose(t);
    H5Aclose(a);
  }
  H5Dclose(d);
  H5Fclose(f);
  return units;
}

bool exists(const std::string& file, const std::string& path) {
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  const bool e = H5Lexists(f, path.c_str(), H5P_DEFAULT) > 0;
  H5Fclose(f);
  return e;
}

void checkRun(const std::string& scenario, const std::set<std::string>& mustHave, const std::set<std::string>& mustLack) {
  SCOPED_TRACE(scenario);
  const Run run = runBundled(scenario);
  const Recording& rec = run.r.rec;
  ASSERT_GT(rec.samples(), 1u);
  const std::string file = (test::processTempDir("result_channels") / "r.h5").string();
  writeResultHdf5(file, run.s, run.r);
  for (const ResultChannel& c : resultChannels()) {
    SCOPED_TRACE(c.path);
    const bool recorded = isRecorded(c, rec);
    if (mustHave.count(c.path)) EXPECT_TRUE(recorded);
    if (mustLack.count(c.path)) EXPECT_FALSE(recorded);
    std::visit(
        [&](const auto& col) {
          const auto& v = rec.*(col.data);
          using T = typename std::decay_t<decltype(v)>::value_type;
          if (!recorded) {
            EXPECT_TRUE(v.empty());
            EXPECT_FALSE(exists(file, c.path));
            return;
          }
          const size_t k = axisLength(c.axis, rec);
          EXPECT_EQ(v.size(), rec.samples() * (c.axis == Axis::None ? 1 : k));
          const std::vector<uint8_t> bytes = test::readDatasetBytes(file, c.path);
          ASSERT_EQ(bytes.size(), v.size() * sizeof(T));
          const int decimals = storedDecimals(c);
          if (decimals < 0) {  // every bit as recorded
            EXPECT_TRUE(v.empty() || std::memcmp(bytes.data(), v.data(), bytes.size()) == 0);
          } else if constexpr (std::is_floating_point_v<T>) {  // to its stated resolution
            const double half = 0.5 * std::pow(10.0, -decimals) * (1.0 + 1e-6);
            double worst = 0.0;
            for (size_t i = 0; i < v.size(); ++i) {
              T got;
              std::memcpy(&got, bytes.data() + i * sizeof(T), sizeof(T));
              worst = std::max(worst, std::fabs(static_cast<double>(got) - static_cast<double>(v[i])));
            }
            EXPECT_LE(worst, half);
          }
          EXPECT_EQ(unitsOf(file, c.path), c.units ? c.units : "");
        },
        c.column);
  }
}

TEST(ResultChannels, PathsAreUniqueAndFoundByPath) {
  std::set<std::string> seen;
  for (const ResultChannel& c : resultChannels()) {
    EXPECT_TRUE(seen.insert(c.path).second) << c.path;
    EXPECT_EQ(findResultChannel(c.path), &c);
    EXPECT_EQ(c.path[0], '/');
  }
  EXPECT_EQ(findResultChannel("/truth/nothing"), nullptr);
}

TEST(ResultChannels, PassiveBalancingRunRecordsAndWritesItsChannels) {
  checkRun("balance/bench_6s_balancing.yaml", {"/time_s", "/hardware/relay_closed", "/bms/balance_status", "/hardware/balancing"},
           {"/truth/balancer_bus_V"});
}

TEST(ResultChannels, RunWithoutBalancingLacksItsChannels) {
  checkRun("bench_6s_ncr18650_2C.yaml", {"/truth/cell_voltage_V", "/bms/telemetry"},
           {"/bms/balance_status", "/hardware/balancing", "/truth/charger_current_A", "/truth/balancer_bus_V"});
}

TEST(ResultChannels, ActiveBalancerRunRecordsItsBus) {
  checkRun("balance/solar_4s3p_active.yaml", {"/truth/balancer_bus_V", "/truth/balance_current_A"}, {});
}

// issue 28: no inf or NaN reaches a result file. A channel value that is not finite
// makes the write fail naming the channel, its column and the time; nothing is left
// behind (neither the file nor its temporary).
TEST(ResultChannels, WriterRefusesANonFiniteValueNamingChannelAndTime) {
  auto run = runBundled("bench_6s_ncr18650_2C.yaml");
  const fs::path dir = test::freshTempDir("result_channels_", "nonfinite");
  const std::string file = (dir / "r.h5").string();
  Recording& rec = run.r.rec;
  const size_t cells = static_cast<size_t>(rec.cells);
  const size_t row = 3;
  ASSERT_GT(rec.samples(), row);
  const double t = rec.time_s[row];
  struct Poke {
    std::vector<double>* channel;
    size_t index;
    double value;
    std::string expect;
  };
  std::ostringstream at;
  at << "at t = " << t << " s";
  for (const Poke& p : {Poke{&rec.cell_voltage_V, row * cells + 2, -INFINITY, "the channel /truth/cell_voltage_V[2] (0-based column) is -inf " + at.str()},
                        Poke{&rec.pack_current_A, row, NAN, "the channel /truth/pack_current_A is nan " + at.str()}}) {
    SCOPED_TRACE(p.expect);
    const double kept = (*p.channel)[p.index];
    (*p.channel)[p.index] = p.value;
    std::string e = "<no error>";
    try {
      writeResultHdf5(file, run.s, run.r);
    } catch (const std::runtime_error& err) {
      e = err.what();
    }
    (*p.channel)[p.index] = kept;
    EXPECT_NE(e.find(p.expect), std::string::npos) << e;
    EXPECT_NE(e.find("not written to '" + file + "'"), std::string::npos) << e;
    EXPECT_TRUE(fs::is_empty(dir)) << "a file was left in " << dir;
  }
  run.r.summary.heat_Wh = INFINITY;
  EXPECT_THROW(writeResultHdf5(file, run.s, run.r), std::runtime_error);
  EXPECT_TRUE(fs::is_empty(dir));
  run.r.summary.heat_Wh = 1.0;
  writeResultHdf5(file, run.s, run.r);  // finite again: written
  EXPECT_TRUE(fs::exists(file));
}

}  // namespace
}  // namespace packsim
