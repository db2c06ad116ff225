// Ascending integers as runs: {6, 7, 8, 16, 26, 27} -> "6-8, 16, 26-27" (the warnings'
// and the run's lists of cells, groups, devices and channels).
#pragma once
#include <string>
#include <vector>

namespace packsim {

inline std::string numberRanges(const std::vector<int>& ascending) {
  std::string out;
  for (size_t i = 0; i < ascending.size(); ++i) {
    size_t j = i;
    while (j + 1 < ascending.size() && ascending[j + 1] == ascending[j] + 1) ++j;
    out += (i ? ", " : "") + std::to_string(ascending[i]);
    if (j > i) out += "-" + std::to_string(ascending[j]);
    i = j;
  }
  return out;
}

}  // namespace packsim
