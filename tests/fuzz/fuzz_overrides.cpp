// libFuzzer harness: the override parser and loader. The input's first part (before a
// line "#---") is overrides, one "key=value" a line; the second part is the scenario
// text (base.yaml, the bundled eco-marathon scenario, when absent). Bad input must be a
// ScenarioError.
#include <cstddef>
#include <cstdint>
#include <fstream>
#include <sstream>

#include "core/scenario/overrides.hpp"
#include "core/scenario/scenario_error.hpp"
#include "fuzz_support.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace packsim;
  const std::vector<std::string> parts = fuzz::splitParts(data, size, 2);
  Overrides overrides;
  std::istringstream lines(parts[0]);
  for (std::string line; std::getline(lines, line);) {
    const size_t eq = line.find('=');
    overrides.emplace_back(line.substr(0, eq), eq == std::string::npos ? std::string() : line.substr(eq + 1));
  }
  std::string text;
  if (parts.size() > 1) {
    text = parts[1];
  } else {
    std::ifstream in(fuzz::scratchDir() + "/base.yaml");
    std::ostringstream os;
    os << in.rdbuf();
    text = os.str();
  }
  try {
    loadScenarioWithOverrides(text, overrides, "fuzz.yaml", fuzz::scratchDir());
  } catch (const ScenarioError&) {
  }
  return 0;
}
