#include "core/scenario/csv_profile.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <tuple>

#include "core/scenario/scenario_error.hpp"

namespace packsim {

namespace {

struct Cell {
  std::string text;
  int column = 1;  // 1-based character position in the line
};

std::string trim(const std::string& s) {
  const size_t a = s.find_first_not_of(" \t\r");
  if (a == std::string::npos) return "";
  const size_t b = s.find_last_not_of(" \t\r");
  return s.substr(a, b - a + 1);
}

std::string unquote(const std::string& s) {
  return s.size() >= 2 && s.front() == '"' && s.back() == '"' ? s.substr(1, s.size() - 2) : s;
}

// The separator the header row uses: ';' or tab if present, else ','.
char separatorOf(const std::string& header) {
  if (header.find(';') != std::string::npos) return ';';
  if (header.find('\t') != std::string::npos && header.find(',') == std::string::npos) return '\t';
  return ',';
}

std::vector<Cell> splitRow(const std::string& line, char sep) {
  std::vector<Cell> cells;
  size_t start = 0;
  while (true) {
    const size_t end = line.find(sep, start);
    const std::string raw = line.substr(start, end == std::string::npos ? std::string::npos : end - start);
    const size_t lead = raw.find_first_not_of(" \t\r");
    cells.push_back({trim(raw), static_cast<int>(start + (lead == std::string::npos ? 0 : lead)) + 1});
    if (end == std::string::npos) break;
    start = end + 1;
  }
  return cells;
}

std::string joined(const std::vector<std::string>& names) {
  std::string s;
  for (const std::string& n : names) s += (s.empty() ? "" : ", ") + n;
  return s;
}

}  // namespace

CsvProfile readProfileCsv(const std::string& path) { return readProfileCsv(path, CsvColumns{}); }

CsvProfile readProfileCsv(const std::string& path, const CsvColumns& want) {
  std::ifstream in(path);
  if (!in) throw ScenarioError(path, 0, 0, "", "cannot open CSV file");
  CsvProfile p;
  std::string line;
  int lineNo = 0;
  char sep = 0;
  std::vector<std::string> names;
  size_t timeCol = 0, valueCol = 0;
  while (std::getline(in, line)) {
    ++lineNo;
    const std::string t = trim(line);
    if (t.empty() || t[0] == '#') continue;
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
                                "csv: {file, time_column, current_column or power_column}), got '" + t + "'");
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
                            "no column '" + name + "' in the header (columns: " + joined(names) + ")" +
                                (near.empty() ? "" : "; did you mean '" + near + "'?"));
      }
      continue;
    }
    const std::vector<Cell> cells = splitRow(line, sep);
    if (cells.size() != names.size())
      throw ScenarioError(path, lineNo, 0, "", "expected " + std::to_string(names.size()) + " columns (as the header: " +
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
  if (sep == 0) throw ScenarioError(path, 0, 0, "", "empty CSV: expected the header 'time_s,current_A'");
  if (p.time_s.size() < 2) throw ScenarioError(path, lineNo, 0, "", "a profile needs at least 2 points");
  return p;
}

}  // namespace packsim
