#include "core/scenario/csv_profile.hpp"

#include <cmath>
#include <fstream>
#include <sstream>

#include "core/scenario/scenario_error.hpp"

namespace packsim {

namespace {

std::string trim(const std::string& s) {
  const size_t a = s.find_first_not_of(" \t\r");
  if (a == std::string::npos) return "";
  const size_t b = s.find_last_not_of(" \t\r");
  return s.substr(a, b - a + 1);
}

std::vector<std::string> splitRow(const std::string& line) {
  std::vector<std::string> cells;
  std::stringstream ss(line);
  std::string cell;
  while (std::getline(ss, cell, ',')) cells.push_back(trim(cell));
  if (!line.empty() && line.back() == ',') cells.emplace_back();
  return cells;
}

}  // namespace

CsvProfile readProfileCsv(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw ScenarioError(path, 0, 0, "", "cannot open CSV file");
  std::string kColumns[2] = {"time_s", "current_A"};
  CsvProfile p;
  std::string line;
  int lineNo = 0;
  bool header = false;
  while (std::getline(in, line)) {
    ++lineNo;
    const std::string t = trim(line);
    if (t.empty() || t[0] == '#') continue;
    const std::vector<std::string> cells = splitRow(t);
    if (!header) {
      if (cells.size() != 2 || cells[0] != kColumns[0] || (cells[1] != "current_A" && cells[1] != "power_W"))
        throw ScenarioError(path, lineNo, 1, "",
                            "expected the header 'time_s,current_A' or 'time_s,power_W', got '" + t + "'");
      kColumns[1] = cells[1];
      p.power = cells[1] == "power_W";
      header = true;
      continue;
    }
    if (cells.size() != 2)
      throw ScenarioError(path, lineNo, 0, "", "expected 2 columns (time_s," + kColumns[1] + "), got " + std::to_string(cells.size()));
    double v[2];
    int column = 1;
    for (int c = 0; c < 2; ++c) {
      char* end = nullptr;
      v[c] = std::strtod(cells[c].c_str(), &end);
      if (cells[c].empty() || *end != '\0' || !std::isfinite(v[c]))
        throw ScenarioError(path, lineNo, column, kColumns[c], "'" + cells[c] + "' is not a finite number");
      column += static_cast<int>(cells[c].size()) + 1;
    }
    if (p.time_s.empty() && v[0] != 0.0)
      throw ScenarioError(path, lineNo, 1, "time_s", "the first point must be at time 0");
    if (!p.time_s.empty() && !(v[0] > p.time_s.back())) {
      std::ostringstream os;
      os << "time must increase strictly: " << v[0] << " after " << p.time_s.back();
      throw ScenarioError(path, lineNo, 1, "time_s", os.str());
    }
    p.time_s.push_back(v[0]);
    p.value.push_back(v[1]);
  }
  if (!header) throw ScenarioError(path, 0, 0, "", "empty CSV: expected the header 'time_s,current_A'");
  if (p.time_s.size() < 2) throw ScenarioError(path, lineNo, 0, "", "a profile needs at least 2 points");
  return p;
}

}  // namespace packsim
