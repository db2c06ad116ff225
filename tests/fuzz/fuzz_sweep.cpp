// libFuzzer harness: the sweep loader (grid, zip, monte_carlo), with base.yaml (the
// bundled eco-marathon scenario) beside it. Bad input must be a ScenarioError.
#include <cstddef>
#include <cstdint>

#include "core/batch/sweep.hpp"
#include "core/scenario/scenario_error.hpp"
#include "fuzz_support.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace packsim;
  try {
    // Without the per-value scenario loads (loadScenarioWithOverrides: fuzz_overrides'
    // harness), which would cut this harness from thousands of inputs a second to tens.
    loadSweepText(std::string(reinterpret_cast<const char*>(data), size), "sweep.yaml", fuzz::scratchDir(),
                  ValueCheck::Skip);
  } catch (const ScenarioError&) {
  }
  return 0;
}
