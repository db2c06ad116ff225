#include "core/scenario/csv_table.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <sstream>

#include "core/scenario/files_read.hpp"

namespace packsim::csv {

TableReader::TableReader(const std::string& path) : path_(path) {
  noteFileRead(path);
  std::error_code ec;
  if (std::filesystem::exists(path, ec) && !std::filesystem::is_regular_file(path, ec))
    throw ScenarioError(path, 0, 0, "", "not a CSV file (it is a folder or a device)");
  in_.open(path, std::ios::binary);
  if (!in_) throw ScenarioError(path, 0, 0, "", "cannot open CSV file");
}

bool TableReader::readHeader() {
  if (!nextDataLine(in_, text_, lineNo_)) return false;
  sep_ = separatorOf(text_);
  for (const Cell& c : splitRow(text_, sep_)) names_.push_back(unquote(c.text));
  return true;
}

bool TableReader::nextRow() {
  if (!nextDataLine(in_, text_, lineNo_)) return false;
  cells_ = splitRow(text_, sep_);
  if (cells_.size() != names_.size())
    throw ScenarioError(path_, lineNo_, cells_.size() > names_.size() ? cells_[names_.size()].column : 1, "",
                        "expected " + std::to_string(names_.size()) + " columns (as the header: " + joined(names_) +
                            "), got " + std::to_string(cells_.size()));
  return true;
}

std::optional<size_t> TableReader::column(const char* name) const {
  const auto it = std::find(names_.begin(), names_.end(), name);
  if (it == names_.end()) return std::nullopt;
  return static_cast<size_t>(it - names_.begin());
}

ScenarioError TableReader::missing(const std::string& what, const std::string& expected) const {
  const std::string near = closestMatch(expected, names_);
  return ScenarioError(path_, lineNo_, 1, "",
                       "no " + what + " column in the header (columns as read: " + joined(names_) + ")" +
                           (near.empty() ? "" : "; did you mean '" + near + "'?"));
}

ScenarioError TableReader::errorAt(size_t col, const std::string& message) const {
  return ScenarioError(path_, lineNo_, cells_[col].column, names_[col], message);
}

double TableReader::value(size_t col, double lo, double hi, const char* unit) const {
  const Cell& c = cells_[col];
  std::string text = unquote(c.text);
  if (sep_ == ';') std::replace(text.begin(), text.end(), ',', '.');  // a decimal comma
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || !std::isfinite(v)) throw errorAt(col, "'" + c.text + "' is not a finite number");
  if (v < lo || v > hi) {
    std::ostringstream os;
    os << "'" << c.text << "' is out of range; allowed [" << lo << ", " << hi << "] " << unit;
    throw errorAt(col, os.str());
  }
  return v;
}

}  // namespace packsim::csv
