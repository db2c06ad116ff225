// The CLI subcommands as plain functions (testable without a process).
#pragma once
#include <cstdint>
#include <optional>
#include <string>

namespace packsim {

struct RunOptions {
  std::string scenario;  // empty: the bundled default
  std::string output;    // empty: packsim-results/<name>.h5
  std::optional<uint64_t> seed;
  bool quiet = false;
};

std::string bundledScenarioDir();
std::string defaultScenarioPath();
int cmdRun(const RunOptions& o);

}  // namespace packsim
