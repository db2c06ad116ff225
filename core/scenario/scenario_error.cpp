#include "core/scenario/scenario_error.hpp"

#include <algorithm>
#include <cctype>
#include <vector>

namespace packsim {

namespace {

std::string location(const std::string& file, int line, int column) {
  std::string s = file.empty() ? "<input>" : file;
  if (line > 0) s += ":" + std::to_string(line);
  if (column > 0) s += ":" + std::to_string(column);
  return s;
}

size_t editDistance(const std::string& a, const std::string& b) {
  std::vector<size_t> prev(b.size() + 1), cur(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) prev[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    cur[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const bool same = std::tolower(static_cast<unsigned char>(a[i - 1])) ==
                        std::tolower(static_cast<unsigned char>(b[j - 1]));
      cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, prev[j - 1] + (same ? 0 : 1)});
    }
    std::swap(prev, cur);
  }
  return prev[b.size()];
}

}  // namespace

ScenarioError::ScenarioError(std::string file, int line, int column, std::string field, std::string message)
    : std::runtime_error(location(file, line, column) + ": " + (field.empty() ? "" : field + ": ") + message),
      file_(std::move(file)),
      field_(std::move(field)),
      message_(std::move(message)),
      line_(line),
      column_(column) {}

std::string closestMatch(const std::string& word, const std::vector<std::string>& candidates) {
  std::string best;
  size_t bestD = SIZE_MAX;
  for (const std::string& c : candidates) {
    const size_t d = editDistance(word, c);
    if (d < bestD) {
      bestD = d;
      best = c;
    }
  }
  // Accept up to a third of the word's length in edits (at least 2).
  const size_t limit = std::max<size_t>(2, word.size() / 3);
  return bestD <= limit ? best : std::string();
}

std::string closestMatch(const std::string& word, const std::initializer_list<const char*>& candidates) {
  return closestMatch(word, std::vector<std::string>(candidates.begin(), candidates.end()));
}

}  // namespace packsim
