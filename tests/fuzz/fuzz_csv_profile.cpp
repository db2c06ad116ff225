// libFuzzer harness: the CSV load-profile parser. Bad input must be a ScenarioError.
#include <cstddef>
#include <cstdint>

#include "core/scenario/csv_profile.hpp"
#include "core/scenario/scenario_error.hpp"
#include "fuzz_support.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace packsim;
  const std::string path = fuzz::scratchDir() + "/fuzz.csv";
  fuzz::writeFile(path, std::string(reinterpret_cast<const char*>(data), size));
  try {
    readProfileCsv(path);
  } catch (const ScenarioError&) {
  }
  return 0;
}
