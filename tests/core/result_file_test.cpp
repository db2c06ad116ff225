// Results are never lost (issue 28): `-o` may not name an input of the scenario (its
// file, a file of its extends: chain, its load CSV) -- exit 2 naming both and the input
// untouched; every process writes its own temporary file, so a temporary file of
// another writer does not stop this one, and concurrent writers of one result end with
// one complete file.
#include <gtest/gtest.h>
#include <hdf5.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/io/hdf5_writer.hpp"
#include "core/scenario/load_scenario.hpp"
#include "core/scenario/scenario_inputs.hpp"
#include "test_support.hpp"

namespace packsim {
namespace {

namespace fs = std::filesystem;

const std::string kBin = PACKSIM_BINARY;

std::string readText(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

int runCli(const std::string& args, const fs::path& err) {
  const int rc = std::system((kBin + " run -q " + args + " 2>" + err.string()).c_str());
  return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}

// The duration the result file's /summary holds, or -1 when it does not open.
double resultDuration(const fs::path& file) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (f < 0) return -1.0;
  double d = -1.0;
  const hid_t a = H5Aopen_by_name(f, "/summary", "duration_s", H5P_DEFAULT, H5P_DEFAULT);
  if (a >= 0) {
    if (H5Aread(a, H5T_NATIVE_DOUBLE, &d) < 0) d = -1.0;
    H5Aclose(a);
  }
  H5Fclose(f);
  return d;
}

const std::string kShort = "load: {current_A: 1}\nrun: {duration_s: 20}\n";

TEST(ResultFile, OutputNamingTheScenarioIsRefusedAndTheScenarioKept) {
  const fs::path d = test::freshTempDir("packsim_result_", "scenario");
  const std::string yaml = test::simpleCellYaml() + kShort;
  std::ofstream(d / "s.yaml") << yaml;
  const int rc = runCli((d / "s.yaml").string() + " -o " + (d / "s.yaml").string(), d / "err.txt");
  const std::string err = readText(d / "err.txt");
  EXPECT_EQ(rc, 2) << err;
  EXPECT_NE(err.find("the result file '" + (d / "s.yaml").string() + "' is the scenario file itself;"), std::string::npos) << err;
  EXPECT_EQ(readText(d / "s.yaml"), yaml);
  // The same file through another path (../d/s.yaml) is the same input.
  const fs::path other = d / ".." / d.filename() / "s.yaml";
  EXPECT_EQ(runCli((d / "s.yaml").string() + " -o " + other.string(), d / "err.txt"), 2);
  EXPECT_EQ(readText(d / "s.yaml"), yaml);
}

TEST(ResultFile, OutputNamingAnExtendsBaseOrTheCsvIsRefused) {
  const fs::path d = test::freshTempDir("packsim_result_", "chain");
  std::ofstream(d / "profile.csv") << "time_s,current_A\n0,1\n10,2\n";
  const std::string base = test::simpleCellYaml() + "load: {csv: profile.csv}\nrun: {duration_s: 20}\n";
  std::ofstream(d / "base.yaml") << base;
  std::ofstream(d / "child.yaml") << "extends: base.yaml\nname: child\n";
  const std::string csv = readText(d / "profile.csv");

  int rc = runCli((d / "child.yaml").string() + " -o " + (d / "base.yaml").string(), d / "err.txt");
  std::string err = readText(d / "err.txt");
  EXPECT_EQ(rc, 2) << err;
  EXPECT_NE(err.find("is a file of its extends: chain '" + (d / "base.yaml").string() + "'"), std::string::npos) << err;
  EXPECT_NE(err.find("child.yaml"), std::string::npos) << err;
  EXPECT_EQ(readText(d / "base.yaml"), base);

  rc = runCli((d / "child.yaml").string() + " -o " + (d / "profile.csv").string(), d / "err.txt");
  err = readText(d / "err.txt");
  EXPECT_EQ(rc, 2) << err;
  EXPECT_NE(err.find("is the load CSV"), std::string::npos) << err;
  EXPECT_NE(err.find("profile.csv"), std::string::npos) << err;
  EXPECT_EQ(readText(d / "profile.csv"), csv);

  // A result beside them is written.
  EXPECT_EQ(runCli((d / "child.yaml").string() + " -o " + (d / "out.h5").string(), d / "err.txt"), 0)
      << readText(d / "err.txt");
  EXPECT_DOUBLE_EQ(resultDuration(d / "out.h5"), 20.0);
}

// A scenario's text is parsed for its extends: and csv keys only when it could hold them
// (scenario_inputs.cpp mayNameFiles): a key spelled with an escape still counts, and a
// file without either key is its only input.
TEST(ResultFile, InputsFoundThroughAnEscapedKeyAndNoneInAPlainFile) {
  const fs::path d = test::freshTempDir("packsim_result_", "escaped");
  std::ofstream(d / "profile.csv") << "time_s,current_A\n0,1\n10,2\n";
  std::ofstream(d / "base.yaml") << test::simpleCellYaml() + "load: {\"\\x63sv\": profile.csv}\nrun: {duration_s: 20}\n";
  std::ofstream(d / "child.yaml") << "\"\\x65xtends\": base.yaml\nname: child\n";
  const std::vector<std::string> chain = scenarioInputFiles(loadScenarioFile((d / "child.yaml").string()));
  ASSERT_EQ(chain.size(), 3u);
  EXPECT_EQ(fs::path(chain[1]).filename(), "base.yaml");
  EXPECT_EQ(fs::path(chain[2]).filename(), "profile.csv");
  EXPECT_EQ(runCli((d / "child.yaml").string() + " -o " + (d / "base.yaml").string(), d / "err.txt"), 2);

  std::ofstream(d / "plain.yaml") << test::simpleCellYaml() + kShort;
  const std::vector<std::string> alone = scenarioInputFiles(loadScenarioFile((d / "plain.yaml").string()));
  ASSERT_EQ(alone.size(), 1u);
  EXPECT_EQ(fs::path(alone[0]).filename(), "plain.yaml");
}

// Another writer's temporary file (here one that cannot be replaced: a folder) is not
// this run's: it writes its own and renames it.
TEST(ResultFile, AnotherWritersTemporaryFileDoesNotStopThisRun) {
  const fs::path d = test::freshTempDir("packsim_result_", "foreign_tmp");
  std::ofstream(d / "s.yaml") << test::simpleCellYaml() + kShort;
  fs::create_directories(d / "out.h5.tmp");
  const int rc = runCli((d / "s.yaml").string() + " -o " + (d / "out.h5").string(), d / "err.txt");
  EXPECT_EQ(rc, 0) << readText(d / "err.txt");
  EXPECT_DOUBLE_EQ(resultDuration(d / "out.h5"), 20.0);
  EXPECT_TRUE(fs::is_directory(d / "out.h5.tmp"));  // the other writer's file is left alone
}

TEST(ResultFile, TemporaryNamesAreThisProcesssOwn) {
  const std::string a = uniqueTemporaryName("x/out.h5"), b = uniqueTemporaryName("x/out.h5");
  EXPECT_EQ(a.rfind("x/out.h5.tmp." + std::to_string(getpid()) + ".", 0), 0u) << a;
  EXPECT_NE(a, b);
}

// Four `packsim run` processes writing the same -o at once: all succeed (none loses its
// result to a failed rename), one complete result file is left and no temporary file.
TEST(ResultFile, ConcurrentWritersEndWithOneCompleteFile) {
  const fs::path d = test::freshTempDir("packsim_result_", "concurrent");
  std::ofstream(d / "s.yaml") << test::simpleCellYaml() + "load: {current_A: 1}\nrun: {duration_s: 600}\n";
  const fs::path out = d / "out.h5";
  std::vector<pid_t> pids;
  for (int i = 0; i < 4; ++i) {
    const std::string cmd = "exec " + kBin + " run -q " + (d / "s.yaml").string() + " -o " + out.string() + " 2>" +
                            (d / ("err" + std::to_string(i) + ".txt")).string();
    const pid_t pid = fork();
    if (pid == 0) {
      execl("/bin/sh", "sh", "-c", cmd.c_str(), static_cast<char*>(nullptr));
      _exit(127);
    }
    pids.push_back(pid);
  }
  for (size_t i = 0; i < pids.size(); ++i) {
    int status = 0;
    waitpid(pids[i], &status, 0);
    const std::string err = readText(d / ("err" + std::to_string(i) + ".txt"));
    EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << err;
    EXPECT_EQ(err.find("cannot rename"), std::string::npos) << err;
    EXPECT_EQ(err.find("error"), std::string::npos) << err;
  }
  EXPECT_DOUBLE_EQ(resultDuration(out), 600.0);
  EXPECT_FALSE(test::temporaryOfExists(out));
}

// The stamp that tells a run another process replaced its result meanwhile.
TEST(ResultFile, StampChangesWhenAnotherProcessReplacesTheFile) {
  const fs::path d = test::freshTempDir("packsim_result_", "stamp");
  const fs::path f = d / "r.h5";
  EXPECT_FALSE(resultFileStamp(f.string()).exists);
  std::ofstream(f) << "one";
  const ResultFileStamp a = resultFileStamp(f.string());
  EXPECT_TRUE(a.exists);
  EXPECT_EQ(a, resultFileStamp(f.string()));
  std::ofstream(d / "r2.h5") << "other";
  fs::rename(d / "r2.h5", f);  // what another writer's rename does
  EXPECT_NE(a, resultFileStamp(f.string()));
}

}  // namespace
}  // namespace packsim
