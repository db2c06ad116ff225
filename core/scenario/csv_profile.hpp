// Reads a load profile table: a header row `time_s,current_A` (or `time_s,power_W`),
// then one row per point.
// Errors name the file, the line and the column that is wrong.
#pragma once
#include <string>
#include <vector>

namespace packsim {

struct CsvProfile {
  std::vector<double> time_s;
  std::vector<double> value;  // A or W
  bool power = false;         // second column is power_W
};

CsvProfile readProfileCsv(const std::string& path);

}  // namespace packsim
