// The run's summary figures as one table: one row per /summary attribute of the result
// file (its name, its type and how it is read from the Summary, which runs have it, and
// where summary.csv puts it). The HDF5 writer writes the rows in table order, the batch
// runner takes summary.csv's leading columns from them, and the test
// (tests/core/summary_fields_test.cpp) checks docs/results.md names every row — so a new
// summary figure is one row here, its field in Summary (result.hpp) and its name in
// docs/results.md. See docs/architecture.md, "To add …".
#pragma once
#include <string>
#include <variant>
#include <vector>

#include "core/sim/result.hpp"

namespace packsim {

using SummaryValue = std::variant<double (*)(const Summary&), long long (*)(const Summary&),
                                  std::string (*)(const Summary&)>;

struct SummaryField {
  const char* name;                             // the /summary attribute, summary.csv's column
  SummaryValue value;                           // float64, int64 (flags 0/1, 1-based numbers) or a string
  bool (*present)(const Summary&) = nullptr;    // nullptr: every run has it
  int csv_rank = 0;  // > 0: among summary.csv's leading columns, in this order; 0: after them, alphabetically
};

// Every row, in the order the result file writes them.
const std::vector<SummaryField>& summaryFields();

// summary.csv's leading columns (the rows with a csv_rank, in that order).
std::vector<std::string> summaryCsvLeadingColumns();

}  // namespace packsim
