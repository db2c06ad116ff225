// The CLI subcommands as plain functions (testable without a process).
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace packsim {

struct RunOptions {
  std::string scenario;  // empty: the bundled default
  std::string output;    // empty: packsim-results/<name>.h5
  std::optional<uint64_t> seed;
  bool quiet = false;
};

struct CheckOptions {
  std::vector<std::string> paths;  // files or directories; empty: the bundled scenarios
};

std::string bundledScenarioDir();
std::string defaultScenarioPath();
int cmdRun(const RunOptions& o);
int cmdCheck(const CheckOptions& o);

}  // namespace packsim
