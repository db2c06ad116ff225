// libFuzzer harness: the scenario loader with extends and presets. The input is up to
// three files separated by lines "#---": a.yaml (loaded), b.yaml and cells/c.yaml, in a
// folder that also holds base.yaml (the bundled eco-marathon scenario), its lap profile
// and the bundled cell presets, so `extends:` and `preset:` reach real files (and each
// other: a.yaml may extend b.yaml which extends a.yaml). Bad input must be a
// ScenarioError; anything else (crash, other exception, sanitizer report) is a finding.
#include <cstddef>
#include <cstdint>

#include "core/scenario/load_scenario.hpp"
#include "core/scenario/scenario_error.hpp"
#include "fuzz_support.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace packsim;
  const std::string& dir = fuzz::scratchDir();
  const std::vector<std::string> parts = fuzz::splitParts(data, size, 3);
  const char* names[] = {"/a.yaml", "/b.yaml", "/cells/c.yaml"};
  for (size_t i = 0; i < 3; ++i) fuzz::writeFile(dir + names[i], i < parts.size() ? parts[i] : std::string());
  try {
    loadScenarioFile(dir + "/a.yaml");
  } catch (const ScenarioError&) {
  }
  return 0;
}
