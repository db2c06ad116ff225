// A CSV table read row by row for a scenario's loaders (route, irradiance): the file
// opened, its header's column names, each row's column count checked against the header,
// and each field read as a finite number in a range — every error a ScenarioError naming
// the file, line, column and the column's name.
#pragma once
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include "core/scenario/csv_text.hpp"
#include "core/scenario/scenario_error.hpp"

namespace packsim::csv {

class TableReader {
 public:
  // Opens `path`; a folder, a device or a missing file is an error.
  explicit TableReader(const std::string& path);

  // The header row: false when the file has no line with content.
  bool readHeader();
  // The next data row, its column count the header's: false at the end of the file.
  bool nextRow();

  std::optional<size_t> column(const char* name) const;
  // The error for a header without `what`, suggesting the column closest to `expected`.
  ScenarioError missing(const std::string& what, const std::string& expected) const;
  // Field `col` of the current row as a finite number in [lo, hi] `unit`.
  double value(size_t col, double lo, double hi, const char* unit) const;
  // An error at field `col` of the current row.
  ScenarioError errorAt(size_t col, const std::string& message) const;

  const Cell& cell(size_t col) const { return cells_[col]; }
  const std::string& name(size_t col) const { return names_[col]; }
  const std::vector<std::string>& names() const { return names_; }
  int line() const { return lineNo_; }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  std::ifstream in_;
  std::string text_;
  int lineNo_ = 0;
  char sep_ = 0;
  std::vector<std::string> names_;
  std::vector<Cell> cells_;
};

}  // namespace packsim::csv
