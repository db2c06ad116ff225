// Shared by the libFuzzer harnesses: a scratch folder per process holding the files a
// fuzz input is split into, next to copies of bundled files it can refer to.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace packsim::fuzz {

// The input split at lines "#---" into at most `max_parts` texts.
std::vector<std::string> splitParts(const uint8_t* data, size_t size, size_t max_parts);
// A folder (created once per process, emptied of the previous input's files) that holds
// copies of the bundled eco_marathon_12s.yaml as base.yaml, profiles/lap.csv and the
// bundled cell presets under cells/.
const std::string& scratchDir();
void writeFile(const std::string& path, const std::string& text);

}  // namespace packsim::fuzz
