// The one error type for bad input (scenario YAML, CSV tables, CLI values): it names
// the file, the line and column, the field, and what would have been valid.
#pragma once
#include <stdexcept>
#include <initializer_list>
#include <string>
#include <vector>

namespace packsim {

class ScenarioError : public std::runtime_error {
 public:
  ScenarioError(std::string file, int line, int column, std::string field, std::string message);
  const std::string& file() const { return file_; }
  int line() const { return line_; }      // 1-based, 0 if unknown
  int column() const { return column_; }  // 1-based, 0 if unknown
  const std::string& field() const { return field_; }
  const std::string& message() const { return message_; }

 private:
  std::string file_, field_, message_;
  int line_, column_;
};

// Closest candidate by edit distance (case-insensitive), or "" if none is close.
std::string closestMatch(const std::string& word, const std::initializer_list<const char*>& candidates);
std::string closestMatch(const std::string& word, const std::vector<std::string>& candidates);

}  // namespace packsim
