// Strict reading of one YAML mapping into typed values. Every accessor declares its
// key; finish() then rejects any key that was not declared, suggesting the closest
// declared one. Values are checked for type and range at the line they sit on.
#pragma once
#include <yaml-cpp/yaml.h>

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/scenario/scenario_error.hpp"

namespace packsim {

// The values a number may take. Both ends are finite: every key states how large a
// value can be (core/scenario/value_ranges.hpp has the bounds many keys share); a range
// without an end is a programming error (std::logic_error).
struct Range {
  double lo;
  double hi;
  bool lo_open = false;  // lo itself not allowed
  bool hi_open = false;
  Range(double lo_, double hi_, bool lo_open_ = false, bool hi_open_ = false);
  static Range positive(double hi) { return {0.0, hi, true, false}; }  // (0, hi]
  static Range nonNegative(double hi) { return {0.0, hi, false, false}; }  // [0, hi]
  static Range closed(double lo, double hi) { return {lo, hi, false, false}; }
  static Range symmetric(double bound) { return {-bound, bound, false, false}; }  // [-bound, bound]
  bool contains(double v) const;
  std::string describe() const;
};

class YamlMap {
 public:
  YamlMap(const YAML::Node& node, std::string file, std::string path);

  const std::string& path() const { return path_; }
  const std::string& file() const { return file_; }
  const YAML::Node& raw() const { return node_; }
  bool has(const std::string& key);

  double number(const std::string& key, Range r);  // required
  double number(const std::string& key, double fallback, Range r);
  long integer(const std::string& key, long lo, long hi);  // required
  long integer(const std::string& key, long fallback, long lo, long hi);
  bool boolean(const std::string& key, bool fallback);
  std::string string(const std::string& key);  // required
  std::string string(const std::string& key, const std::string& fallback);
  std::string choice(const std::string& key, const std::string& fallback, const std::vector<std::string>& allowed);
  std::vector<double> numbers(const std::string& key, Range r, size_t min_len = 1);
  std::vector<long> integers(const std::string& key, long lo, long hi, size_t min_len = 1);

  YamlMap map(const std::string& key);  // required child mapping
  std::optional<YamlMap> optionalMap(const std::string& key);
  // The child mapping, or an empty one at its path when the key is absent: reading its
  // defaults records them for `packsim show` like any other default.
  YamlMap mapOrEmpty(const std::string& key);
  // Elements of a sequence of mappings.
  std::vector<YamlMap> mapList(const std::string& key);
  YAML::Node node(const std::string& key);  // declared, raw (caller checks it)

  ScenarioError errorAt(const std::string& key, const std::string& message) const;
  ScenarioError errorAt(const YAML::Node& n, const std::string& field, const std::string& message) const;
  ScenarioError error(const std::string& message) const;  // at the mapping itself

  // Rejects undeclared keys. Call after reading every field.
  void finish() const;

 private:
  std::string fieldName(const std::string& key) const;
  YAML::Node required(const std::string& key);
  double toNumber(const YAML::Node& n, const std::string& field, Range r) const;
  // The value read, for `packsim show` (core/scenario/provenance.hpp).
  void noteValue(const std::string& key, const YAML::Node& n) const;
  void noteDefault(const std::string& key, const std::string& valueYaml) const;

  YAML::Node node_;
  std::string file_;
  std::string path_;
  std::vector<std::string> declared_;
};

// A plain decimal number's value (-?D+(.D+)?([eE][-+]?D+)?), the same double as yaml-cpp's
// as<double>, without its stream; false for any other text (yaml-cpp reads it then).
bool plainDecimal(const std::string& s, double& v);

// A quoted scalar ("5", '5', or one tagged !!str) is text in YAML, not a number or a
// true/false: where one of those belongs it is refused with this message, naming the
// field, instead of read as one. (Accepting "5" would make a JSON string from a script or
// a spreadsheet cell a silent number; every number-taking key refuses it alike.)
bool quotedScalar(const YAML::Node& n);
std::string quotedValueMessage(const YAML::Node& n, const std::string& expected);

// Parses YAML text, turning parser errors into ScenarioError.
YAML::Node parseYaml(const std::string& text, const std::string& file);

}  // namespace packsim
