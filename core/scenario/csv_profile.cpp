#include "core/scenario/csv_profile.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <tuple>

#include "core/scenario/csv_text.hpp"
#include "core/scenario/files_read.hpp"
#include "core/scenario/scenario_error.hpp"
#include "core/scenario/value_ranges.hpp"

namespace packsim {

using namespace csv;

CsvProfile readProfileCsv(const std::string& path) { return readProfileCsv(path, CsvColumns{}); }

CsvProfile readProfileCsv(const std::string& path, const CsvColumns& want) {
  std::error_code ec;
  if (std::filesystem::exists(path, ec) && !std::filesystem::is_regular_file(path, ec))
    throw ScenarioError(path, 0, 0, "", "not a CSV file (it is a folder or a device)");
  noteFileRead(path);
  std::ifstream in(path, std::ios::binary);  // binary: a CR of CRLF line ends is trimmed below
  if (!in) throw ScenarioError(path, 0, 0, "", "cannot open CSV file");
  CsvProfile p;
  std::string line;
  int lineNo = 0;
  char sep = 0;
  std::vector<std::string> names;
  size_t timeCol = 0, valueCol = 0;
  while (nextDataLine(in, line, lineNo)) {
    if (sep == 0) {  // the header row
      sep = separatorOf(line);
      for (const Cell& c : splitRow(line, sep)) names.push_back(unquote(c.text));
      auto find = [&](const std::string& name) { return std::find(names.begin(), names.end(), name) - names.begin(); };
      const bool defaults = want.value.empty() && want.time == "time_s";
      timeCol = static_cast<size_t>(find(want.time));
      if (want.value.empty()) {
        const size_t cur = static_cast<size_t>(find("current_A")), pow = static_cast<size_t>(find("power_W"));
        if (timeCol == names.size() || (cur == names.size()) == (pow == names.size())) {
          if (defaults)
            throw ScenarioError(path, lineNo, 1, "",
                                "expected the header 'time_s,current_A' or 'time_s,power_W' (or name the columns: "
                                "csv: {file, time_column, current_column or power_column}); the header as read is '" + visible(trim(line)) + "'");
        }
        valueCol = cur != names.size() ? cur : pow;
        p.power = cur == names.size();
      } else {
        valueCol = static_cast<size_t>(find(want.value));
        p.power = want.power;
      }
      for (const auto& [col, name, key] : {std::tuple{timeCol, want.time, "time_column"},
                                           std::tuple{valueCol, want.value.empty() ? "current_A" : want.value,
                                                      want.value.empty() ? "current_column" : (want.power ? "power_column" : "current_column")}}) {
        if (col < names.size()) continue;
        const std::string near = closestMatch(name, names);
        throw ScenarioError(path, lineNo, 1, key,
                            "no column '" + visible(name) + "' in the header (columns as read: " + joined(names) + ")" +
                                (near.empty() ? "" : "; did you mean '" + near + "'?"));
      }
      continue;
    }
    const std::vector<Cell> cells = splitRow(line, sep);
    if (cells.size() != names.size())
      throw ScenarioError(path, lineNo, cells.size() > names.size() ? cells[names.size()].column : 1, "", "expected " + std::to_string(names.size()) + " columns (as the header: " +
                                                   joined(names) + "), got " + std::to_string(cells.size()));
    double v[2];
    const size_t cols[2] = {timeCol, valueCol};
    for (int k = 0; k < 2; ++k) {
      const Cell& c = cells[cols[k]];
      std::string text = unquote(c.text);
      if (sep == ';') std::replace(text.begin(), text.end(), ',', '.');  // decimal comma
      char* end = nullptr;
      v[k] = std::strtod(text.c_str(), &end);
      if (text.empty() || *end != '\0' || !std::isfinite(v[k]))
        throw ScenarioError(path, lineNo, c.column, names[cols[k]], "'" + c.text + "' is not a finite number");
    }
    v[0] *= want.time_scale;
    // The same bounds as a load's keys (core/scenario/value_ranges.hpp): time up to 30
    // days, a current up to 100 kA, a power up to 100 MW (after `scale`).
    const double maxValue = p.power ? limits::kMaxPower_W : limits::kMaxCurrent_A;
    if (v[0] > limits::kMaxTime_s) {
      std::ostringstream os;
      os << "'" << cells[timeCol].text << "'";
      if (want.time_scale != 1.0) os << " (scaled: " << v[0] << " s)";
      os << (want.time_scale != 1.0 ? "" : " s") << " is out of range; allowed [0, " << limits::kMaxTime_s << "] s (30 days)";
      throw ScenarioError(path, lineNo, cells[timeCol].column, names[timeCol], os.str());
    }
    if (!(std::fabs(v[1] * want.scale) <= maxValue)) {
      std::ostringstream os;
      os << "'" << cells[valueCol].text << "'";
      if (want.scale != 1.0) os << " (scaled: " << v[1] * want.scale << ")";
      os << " is out of range; allowed [-" << maxValue << ", " << maxValue << "] " << (p.power ? "W" : "A");
      throw ScenarioError(path, lineNo, cells[valueCol].column, names[valueCol], os.str());
    }
    if (want.check) {
      const std::string why = want.check(v[1] * want.scale, p.power);
      if (!why.empty()) throw ScenarioError(path, lineNo, cells[valueCol].column, names[valueCol], why);
    }
    if (p.time_s.empty() && v[0] != 0.0)
      throw ScenarioError(path, lineNo, cells[timeCol].column, names[timeCol], "the first point must be at time 0");
    if (!p.time_s.empty() && !(v[0] > p.time_s.back())) {
      std::ostringstream os;
      os << "time must increase strictly: " << v[0] << " after " << p.time_s.back();
      throw ScenarioError(path, lineNo, cells[timeCol].column, names[timeCol], os.str());
    }
    p.time_s.push_back(v[0]);
    p.value.push_back(v[1] * want.scale);
  }
  if (sep == 0)
    throw ScenarioError(path, std::max(lineNo, 1), 1, "",
                        "empty CSV (" + std::to_string(lineNo) + " lines, none but blanks and # comments): expected a "
                        "header such as 'time_s,current_A'");
  if (p.time_s.size() < 2)
    throw ScenarioError(path, lineNo, 1, names[timeCol],
                        "a profile needs at least 2 points, got " + std::to_string(p.time_s.size()));
  return p;
}

}  // namespace packsim
