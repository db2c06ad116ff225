#include "core/scenario/column_units.hpp"

#include <utility>

namespace packsim {

namespace {

// The last word of a column name: after the last '_', ' ', '(', '[', '/' or '-', with a
// closing ')' or ']' and spaces dropped ("Time (ms)" -> "ms", "current_mA" -> "mA").
std::string lastWord(std::string name) {
  while (!name.empty() && (name.back() == ')' || name.back() == ']' || name.back() == ' ')) name.pop_back();
  const size_t at = name.find_last_of("_ ([/-");
  return at == std::string::npos ? std::string() : name.substr(at + 1);
}

template <size_t N>
NamedUnit lookUp(const std::string& column, const std::pair<const char*, double> (&units)[N]) {
  const std::string word = lastWord(column);
  for (const auto& [unit, factor] : units)
    if (word == unit) return {unit, factor};
  return {};
}

}  // namespace

NamedUnit timeUnitOfName(const std::string& column) {
  static const std::pair<const char*, double> kUnits[] = {{"s", 1.0},     {"sec", 1.0},   {"ms", 1e-3},
                                                          {"msec", 1e-3}, {"us", 1e-6},   {"min", 60.0},
                                                          {"h", 3600.0},  {"hr", 3600.0}};
  return lookUp(column, kUnits);
}

NamedUnit valueUnitOfName(const std::string& column, bool power) {
  static const std::pair<const char*, double> kCurrent[] = {{"A", 1.0}, {"mA", 1e-3}, {"kA", 1e3}};
  static const std::pair<const char*, double> kPower[] = {{"W", 1.0}, {"mW", 1e-3}, {"kW", 1e3}, {"MW", 1e6}};
  return power ? lookUp(column, kPower) : lookUp(column, kCurrent);
}

}  // namespace packsim
