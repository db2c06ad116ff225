#include "test_support.hpp"

#include <gtest/gtest.h>

#include <unistd.h>

#include <hdf5.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <stdexcept>

namespace packsim::test {

std::string simpleCellYaml(int series) {
  return "name: simple\n"
         "seed: 3\n"
         "pack:\n"
         "  series: " + std::to_string(series) + "\n"
         "  initial_soc: 0.8\n"
         "  initial_temp_C: 25\n"
         "  cell:\n"
         "    capacity_Ah: 2.0\n"
         "    ocv_V: {poly: [0.8, 3.4]}\n"
         "    r0_ohm: 0.02\n"
         "    rc_pairs: [{r_ohm: 0.01, c_F: 1000}]\n"
         "    heat_capacity_J_per_K: 40\n"
         "    g_ambient_W_per_K: 0.1\n"
         "hardware:\n"
         "  cell_adc: {lsb_uV: 100, bits: 16, noise_mV_rms: 0}\n"
         "  thermistors: {at_groups: [1]}\n"
         "  current_sense: {shunt_ohm: 0.001, amp_gain: 20, noise_A_rms: 0}\n"
         "ambient: {temp_C: 25}\n";
}

Scenario scenarioFromYaml(const std::string& yaml) { return loadScenarioText(yaml, "test.yaml", scenarioDir()); }

std::string scenarioErrorOf(const std::function<void()>& load) {
  try {
    load();
  } catch (const ScenarioError& e) {
    return e.what();
  }
  return "<no error>";
}

std::string yamlErrorOf(const std::string& yaml) {
  return scenarioErrorOf([&] { scenarioFromYaml(yaml); });
}

std::string fileErrorOf(const std::filesystem::path& file) {
  return scenarioErrorOf([&] { loadScenarioFile(file.string()); });
}

namespace {

// The folders processTempDir made, removed when the test process exits normally, so a
// suite run leaves nothing in the temp folder (thousands of folders a day otherwise).
// Only the process that made them removes them (a forked child that exits keeps its
// parent's), and PACKSIM_KEEP_TEST_FILES keeps them for a look after a failure.
class MadeFolders {
 public:
  void add(const std::filesystem::path& d) {
    for (const auto& f : folders_)
      if (f == d) return;
    folders_.push_back(d);
  }
  ~MadeFolders() {
    if (::getpid() != owner_ || std::getenv("PACKSIM_KEEP_TEST_FILES") != nullptr) return;
    std::error_code ec;
    for (const auto& f : folders_) std::filesystem::remove_all(f, ec);
  }

 private:
  pid_t owner_ = ::getpid();
  std::vector<std::filesystem::path> folders_;
};

MadeFolders& madeFolders() {
  static MadeFolders made;
  return made;
}

}  // namespace

std::filesystem::path processTempDir(const std::string& name) {
  const std::filesystem::path d = std::filesystem::temp_directory_path() / (name + "_" + std::to_string(::getpid()));
  std::filesystem::create_directories(d);
  madeFolders().add(d);
  return d;
}

std::filesystem::path freshTempDir(const std::string& prefix, const std::string& name) {
  namespace fs = std::filesystem;
  const fs::path d = processTempDir(prefix + name);
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

bool temporaryOfExists(const std::filesystem::path& result) {
  namespace fs = std::filesystem;
  const fs::path dir = result.has_parent_path() ? result.parent_path() : fs::path(".");
  const std::string prefix = result.filename().string() + ".tmp";
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec))
    if (e.path().filename().string().compare(0, prefix.size(), prefix) == 0) return true;
  return false;
}

double eventTime(const RunResult& r, const std::string& kind, const std::string& detail) {
  for (const Event& e : r.events)
    if (e.kind == kind && e.detail.compare(0, detail.size(), detail) == 0) return e.time_s;
  return -1.0;
}

std::vector<const Event*> eventsOf(const RunResult& r, const std::string& kind) {
  std::vector<const Event*> out;
  for (const Event& e : r.events)
    if (e.kind == kind) out.push_back(&e);
  return out;
}

std::filesystem::path writeTempFile(const std::string& folder, const std::string& name, const std::string& text) {
  const std::filesystem::path dir = processTempDir(folder);
  std::filesystem::create_directories(dir);
  std::ofstream(dir / name) << text;
  return dir / name;
}

size_t sampleAt(const Recording& rec, double t) {
  for (size_t i = 0; i < rec.time_s.size(); ++i)
    if (std::fabs(rec.time_s[i] - t) < 1e-9) return i;
  throw std::runtime_error("no sample at t = " + std::to_string(t));
}

std::string scenarioDir() { return PACKSIM_SCENARIO_DIR; }

std::vector<uint8_t> readDatasetBytes(const std::string& file, const std::string& dataset) {
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (f < 0) throw std::runtime_error("cannot open " + file);
  const hid_t d = H5Dopen2(f, dataset.c_str(), H5P_DEFAULT);
  if (d < 0) {
    H5Fclose(f);
    throw std::runtime_error("no dataset " + dataset);
  }
  const hid_t type = H5Dget_type(d);
  const hid_t space = H5Dget_space(d);
  const size_t n = static_cast<size_t>(H5Sget_simple_extent_npoints(space)) * H5Tget_size(type);
  std::vector<uint8_t> buf(n);
  if (n > 0 && H5Tget_class(type) != H5T_COMPOUND) H5Dread(d, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, buf.data());
  H5Sclose(space);
  H5Tclose(type);
  H5Dclose(d);
  H5Fclose(f);
  return buf;
}

void expectBleedIsTheSocLost(const Recording& rec, const std::vector<double>& bleed_As, double capacity_As,
                             double slack_As) {
  const size_t n = bleed_As.size(), last = rec.samples() - 1;
  size_t ref = 0;
  for (size_t c = 1; c < n; ++c)
    if (bleed_As[c] < bleed_As[ref]) ref = c;
  EXPECT_LT(bleed_As[ref], 1.0);
  auto gained = [&](size_t c) { return rec.cell_soc[last * n + c] - rec.cell_soc[c]; };
  for (size_t c = 0; c < n; ++c) {
    const double lost_As = capacity_As * (gained(c) - gained(ref));
    EXPECT_NEAR(-lost_As, bleed_As[c], 0.005 * bleed_As[c] + slack_As) << "cell " << c + 1;
  }
}

}  // namespace packsim::test
