// Reads a load profile table: a header row naming the columns, then one row per point.
// The time column and one value column (a current in A or a power in W) are picked by
// name; other columns are ignored. Fields are separated by commas, or by semicolons
// (then a decimal comma is read too: "1,5" is 1.5) or tabs, as the header row uses.
// `scale` multiplies the values (0.001 for a column in mA or mW, -1 to flip a sign
// convention), `time_scale` the times (0.001 for a column in ms); time is then in seconds.
// Errors name the file, the line and the column that is wrong.
#pragma once
#include <functional>
#include <string>
#include <vector>

namespace packsim {

struct CsvProfile {
  std::vector<double> time_s;
  std::vector<double> value;  // A or W, scaled
  bool power = false;         // the value column is a power
};

struct CsvColumns {
  std::string time = "time_s";
  std::string value;   // "": the column named current_A or power_W
  bool power = false;  // with `value`: it is a power (W), else a current (A)
  double scale = 1.0;
  double time_scale = 1.0;
  // A further check of each scaled value (A or W, and whether it is a power): "" when
  // it passes, else why not (the error then names the file, line and column).
  std::function<std::string(double value, bool power)> check;
};

CsvProfile readProfileCsv(const std::string& path);  // the default columns
CsvProfile readProfileCsv(const std::string& path, const CsvColumns& columns);

}  // namespace packsim
