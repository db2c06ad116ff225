#include "core/scenario/yaml_map.hpp"

#include <algorithm>
#include <charconv>
#include <filesystem>
#include <iomanip>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <unordered_set>
#include <utility>
#include <vector>

#include "core/scenario/provenance.hpp"
#include "core/scenario/decimal_text.hpp"

namespace packsim {

Range::Range(double lo_, double hi_, bool lo_open_, bool hi_open_)
    : lo(lo_), hi(hi_), lo_open(lo_open_), hi_open(hi_open_) {
  // (lo > hi is allowed: a key with no valid value here, e.g. a thermistor number in a
  // pack without thermistors, is then an error naming the empty range.)
  if (!std::isfinite(lo) || !std::isfinite(hi)) throw std::logic_error("a scenario key's range needs two finite ends");
}

bool Range::contains(double v) const {
  if (lo_open ? !(v > lo) : !(v >= lo)) return false;
  if (hi_open ? !(v < hi) : !(v <= hi)) return false;
  return true;
}

std::string Range::describe() const {
  // A whole bound in all its digits: 6 significant digits printed the seed's 2147483647 as
  // 2.14748e+09, a bound no value could be near.
  auto fmt = [](double v) {
    std::ostringstream os;
    if (v == std::floor(v) && std::fabs(v) < 1e15) os << std::fixed << std::setprecision(0);
    os << v;
    return os.str();
  };
  return std::string(lo_open ? "(" : "[") + fmt(lo) + ", " + fmt(hi) + (hi_open ? ")" : "]");
}

namespace {

// yaml-cpp keeps both entries of a repeated key and lookups see only one of them: a
// repeated key is an error naming both places. Aliases are followed, so a document
// that expands (through aliases) beyond kMaxYamlNodes nodes is refused here too.
constexpr size_t kMaxYamlNodes = 200000;

void rejectDuplicateKeys(const YAML::Node& n, const std::string& file, int depth, size_t& visited) {
  const auto here = [&] { return std::make_pair(n.Mark().line + 1, n.Mark().column + 1); };
  if (depth > 64) throw ScenarioError(file, here().first, here().second, "", "nested more than 64 levels deep");
  if (++visited > kMaxYamlNodes)
    throw ScenarioError(file, here().first, here().second, "",
                        "the document expands (through aliases) to more than " + std::to_string(kMaxYamlNodes) + " nodes");
  if (n.IsSequence()) {
    for (const YAML::Node& e : n) rejectDuplicateKeys(e, file, depth + 1, visited);
  } else if (n.IsMap()) {
    std::vector<std::pair<std::string, YAML::Mark>> seen;
    for (auto it = n.begin(); it != n.end(); ++it) {
      const std::string key = it->first.IsScalar() ? it->first.Scalar() : std::string();
      const YAML::Mark at = it->first.Mark();
      for (const auto& [k, first] : seen) {
        if (!it->first.IsScalar() || k != key) continue;
        throw ScenarioError(file, at.line + 1, at.column + 1, key,
                            "duplicate key (first given at line " + std::to_string(first.line + 1) + ", column " +
                                std::to_string(first.column + 1) + ")");
      }
      seen.emplace_back(key, at);
      rejectDuplicateKeys(it->second, file, depth + 1, visited);
    }
  }
}

// A fresh copy of `n` (its scalars' tags kept: a quoted "5" stays text), sharing no node
// with it; the copy has no line and column.
YAML::Node copyTree(const YAML::Node& n) {
  if (n.IsMap()) {
    YAML::Node m(YAML::NodeType::Map);
    for (auto it = n.begin(); it != n.end(); ++it) m.force_insert(copyTree(it->first), copyTree(it->second));
    return m;
  }
  if (n.IsSequence()) {
    YAML::Node q(YAML::NodeType::Sequence);
    for (const YAML::Node& e : n) q.push_back(copyTree(e));
    return q;
  }
  if (!n.IsScalar()) return YAML::Node(YAML::NodeType::Null);
  YAML::Node v(n.Scalar());
  v.SetTag(n.Tag());
  return v;
}

// An alias (`*slow`) is the anchored node itself, not a copy: yaml-cpp edits a node in
// place, so a child's `cell_overvoltage: {delay_ms: 100}` or a --set of it changed the
// `cell_undervoltage: *slow` beside it too, silently. Every use after the first becomes
// a copy of its own. Distinct nodes of a parsed document start at distinct places, so a
// value at a place already seen is an alias of the node there. (A null has no text of
// its own to tell; changing it in place replaces only its own entry.) The entries after
// the replaced one are re-added in order, so every other node keeps its line and column.
void unshareAliases(YAML::Node n, std::unordered_set<size_t>& seen) {
  const auto repeat = [&](const YAML::Node& v) {
    if (v.IsNull() || v.Mark().pos < 0) return false;
    return !seen.insert(static_cast<size_t>(v.Mark().pos)).second;
  };
  if (n.IsMap()) {
    std::vector<std::pair<YAML::Node, YAML::Node>> entries;
    for (auto it = n.begin(); it != n.end(); ++it) entries.emplace_back(it->first, it->second);
    for (size_t i = 0; i < entries.size(); ++i) {
      if (!repeat(entries[i].second)) {
        unshareAliases(entries[i].second, seen);
        continue;
      }
      for (size_t j = i; j < entries.size(); ++j) n.remove(entries[j].first);
      entries[i].second.reset(copyTree(entries[i].second));  // reset: operator= would write through the alias
      for (size_t j = i; j < entries.size(); ++j) n.force_insert(entries[j].first, entries[j].second);
    }
  } else if (n.IsSequence()) {
    std::vector<YAML::Node> items(n.begin(), n.end());
    for (size_t i = 0; i < items.size(); ++i) {
      if (!repeat(items[i])) {
        unshareAliases(items[i], seen);
        continue;
      }
      for (size_t j = items.size(); j-- > i;) n.remove(j);
      items[i].reset(copyTree(items[i]));
      for (size_t j = i; j < items.size(); ++j) n.push_back(items[j]);
    }
  }
}

// YAML indents with spaces only; yaml-cpp's message for a tab ("illegal map value",
// "end of map not found") names no tab. The first line indented with one is named.
std::string tabHint(const std::string& text) {
  size_t line = 1;
  for (size_t i = 0; i < text.size(); ++i) {
    if (text[i] == '\n') {
      ++line;
      continue;
    }
    if (text[i] == '\t' && (i == 0 || text.find_last_not_of(" \t", i) == std::string::npos ||
                             text[text.find_last_not_of(" \t", i)] == '\n'))
      return " (line " + std::to_string(line) + " is indented with a tab; YAML indents with spaces)";
  }
  return "";
}

}  // namespace

YAML::Node parseYaml(const std::string& text, const std::string& file) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::ParserException& e) {
    throw ScenarioError(file, e.mark.line + 1, e.mark.column + 1, "", "YAML syntax error: " + e.msg + tabHint(text));
  }
  size_t visited = 0;
  rejectDuplicateKeys(root, file, 0, visited);
  std::unordered_set<size_t> seen;
  unshareAliases(root, seen);
  return root;
}

YamlMap::YamlMap(const YAML::Node& node, std::string file, std::string path)
    : node_(node), file_(std::move(file)), path_(std::move(path)) {
  if (!node_.IsMap()) throw error("expected a mapping of key: value pairs");
}

std::string YamlMap::fieldName(const std::string& key) const { return path_.empty() ? key : path_ + "." + key; }

ScenarioError YamlMap::errorAt(const YAML::Node& n, const std::string& field, const std::string& message) const {
  const YAML::Mark m = n.Mark();
  const bool known = m.line >= 0;
  // In a scenario merged from an extends: chain a node keeps its own file's line: name
  // the file that set the field, not the one this mapping was read from.
  // The message then says where to change it: in the scenario being loaded, whose keys
  // replace its base's (extends:) or its preset's.
  std::string file = file_;
  std::string where;
  if (const Provenance* p = Provenance::active()) {
    const std::string setBy = p->fileOf(field);
    const std::string self = Provenance::displayName(file_);
    if (!setBy.empty() && setBy != self) {
      file = setBy;
      const std::string base = std::filesystem::path(setBy).filename().string();
      const std::string child = std::filesystem::path(self).filename().string();
      const std::string key = field.substr(0, field.find('['));  // a list is given whole
      // Where to change it, not a claim that the child gave it ("given in f15.yaml replaces
      // it" read as if f15.yaml had, when its bms.tick_ms made the base's interval invalid).
      where = " (the value comes from " + base + "; give " + key + " in " + child + " to replace it)";
    }
  }
  return ScenarioError(file, known ? m.line + 1 : 0, known ? m.column + 1 : 0, field, message + where);
}

ScenarioError YamlMap::errorAt(const std::string& key, const std::string& message) const {
  for (auto it = node_.begin(); it != node_.end(); ++it) {
    if (it->first.Scalar() == key) return errorAt(it->second, fieldName(key), message);
  }
  return error(message);
}

ScenarioError YamlMap::error(const std::string& message) const { return errorAt(node_, path_, message); }

bool YamlMap::has(const std::string& key) {
  if (std::find(declared_.begin(), declared_.end(), key) == declared_.end()) declared_.push_back(key);
  return static_cast<bool>(node_[key]);
}

YAML::Node YamlMap::required(const std::string& key) {
  if (has(key)) return node_[key];
  // A misspelt required key is reported as the misspelling, where it is.
  for (auto it = node_.begin(); it != node_.end(); ++it) {
    const std::string given = it->first.Scalar();
    if (closestMatch(given, {key.c_str()}) == key) {
      const YAML::Mark m = it->first.Mark();
      throw ScenarioError(file_, m.line + 1, m.column + 1, fieldName(given),
                          "unknown key; did you mean '" + key + "'?");
    }
  }
  // The keys given instead (a `value:` where the kind takes `current_A:`) are named.
  std::string given;
  for (auto it = node_.begin(); it != node_.end(); ++it) given += (given.empty() ? "" : ", ") + it->first.Scalar();
  throw error("missing required key '" + key + "'" + (given.empty() ? std::string() : " (given: " + given + ")"));
}

YAML::Node YamlMap::node(const std::string& key) {
  if (has(key)) noteValue(key, node_[key]);
  return node_[key];
}

void YamlMap::noteValue(const std::string& key, const YAML::Node& n) const {
  if (Provenance* p = Provenance::active()) p->recordNode(fieldName(key), n);
}

void YamlMap::noteDefault(const std::string& key, const std::string& valueYaml) const {
  if (Provenance* p = Provenance::active()) p->recordDefault(fieldName(key), valueYaml);
}

// yaml-cpp's value of a plain decimal number (a stream's >>, strtod: correctly rounded)
// by std::from_chars (correctly rounded too: the same double), without the stream
// (~4,700 instructions a number: a long load profile's hundreds of them). Anything else,
// or out of range, false: yaml-cpp then reads it (its value or its error).
bool plainDecimal(const std::string& s, double& v) {
  if (!decimalText(s, true)) return false;
  const char* end = s.data() + s.size();
  const std::from_chars_result r = std::from_chars(s.data(), end, v);
  return r.ec == std::errc() && r.ptr == end;
}

bool quotedScalar(const YAML::Node& n) {
  return n.IsScalar() && (n.Tag() == "!" || n.Tag() == "tag:yaml.org,2002:str");
}

std::string quotedValueMessage(const YAML::Node& n, const std::string& expected) {
  return expected + ", got the text \"" + n.Scalar() + "\" (quoted, so YAML reads it as text): write it without quotes";
}

double YamlMap::toNumber(const YAML::Node& n, const std::string& field, Range r) const {
  if (!n.IsScalar()) throw errorAt(n, field, "expected a number");
  if (quotedScalar(n)) throw errorAt(n, field, quotedValueMessage(n, "expected a number"));
  double v = 0.0;
  try {
    if (!plainDecimal(n.Scalar(), v)) v = n.as<double>();
  } catch (const YAML::Exception&) {
    throw errorAt(n, field, "expected a number, got '" + n.Scalar() + "'; allowed " + r.describe());
  }
  // A NaN or infinity (YAML's .nan, .inf; a Python float('nan')): the range says what fits.
  if (!std::isfinite(v))
    throw errorAt(n, field, "expected a finite number, got '" + n.Scalar() + "'; allowed " + r.describe());
  if (!r.contains(v)) throw errorAt(n, field, n.Scalar() + " is out of range; allowed " + r.describe());
  return v;
}

double YamlMap::number(const std::string& key, Range r) {
  const YAML::Node n = required(key);
  const double v = toNumber(n, fieldName(key), r);
  noteValue(key, n);
  return v;
}

double YamlMap::number(const std::string& key, double fallback, Range r) {
  if (has(key)) return number(key, r);
  noteDefault(key, numberText(fallback));
  return fallback;
}

long YamlMap::integer(const std::string& key, long lo, long hi) {
  const YAML::Node n = required(key);
  const double v = toNumber(n, fieldName(key), Range::closed(static_cast<double>(lo), static_cast<double>(hi)));
  if (v != std::floor(v)) throw errorAt(n, fieldName(key), "expected a whole number, got '" + n.Scalar() + "'");
  noteValue(key, n);
  return static_cast<long>(v);
}

long YamlMap::integer(const std::string& key, long fallback, long lo, long hi) {
  if (has(key)) return integer(key, lo, hi);
  noteDefault(key, std::to_string(fallback));
  return fallback;
}

bool YamlMap::boolean(const std::string& key, bool fallback) {
  if (!has(key)) {
    noteDefault(key, fallback ? "true" : "false");
    return fallback;
  }
  const YAML::Node n = node_[key];
  if (quotedScalar(n)) throw errorAt(n, fieldName(key), quotedValueMessage(n, "expected true or false"));
  try {
    if (n.IsScalar()) {
      const bool v = n.as<bool>();
      noteValue(key, n);
      return v;
    }
  } catch (const YAML::Exception&) {
  }
  throw errorAt(n, fieldName(key), "expected true or false, got '" + (n.IsScalar() ? n.Scalar() : "?") + "'");
}

std::string YamlMap::string(const std::string& key) {
  const YAML::Node n = required(key);
  if (!n.IsScalar()) throw errorAt(n, fieldName(key), "expected a text value");
  noteValue(key, n);
  return n.Scalar();
}

std::string YamlMap::string(const std::string& key, const std::string& fallback) {
  if (has(key)) return string(key);
  noteDefault(key, yamlFlowText(YAML::Node(fallback)));
  return fallback;
}

std::string YamlMap::choice(const std::string& key, const std::string& fallback,
                            const std::vector<std::string>& allowed) {
  const std::string v = string(key, fallback);
  if (std::find(allowed.begin(), allowed.end(), v) != allowed.end()) return v;
  std::string list;
  for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
  const std::string near = closestMatch(v, allowed);
  throw errorAt(key, "'" + v + "' is not one of: " + list + (near.empty() ? "" : " (did you mean '" + near + "'?)"));
}

std::vector<double> YamlMap::numbers(const std::string& key, Range r, size_t min_len) {
  const YAML::Node n = required(key);
  if (!n.IsSequence()) throw errorAt(n, fieldName(key), "expected a list of numbers like [1, 2, 3]");
  if (n.size() < min_len)
    throw errorAt(n, fieldName(key), "expected at least " + std::to_string(min_len) + " values");
  std::vector<double> out;
  for (size_t i = 0; i < n.size(); ++i) out.push_back(toNumber(n[i], fieldName(key) + "[" + std::to_string(i) + "]", r));
  noteValue(key, n);
  return out;
}

std::vector<long> YamlMap::integers(const std::string& key, long lo, long hi, size_t min_len) {
  const std::vector<double> v = numbers(key, Range::closed(static_cast<double>(lo), static_cast<double>(hi)), min_len);
  std::vector<long> out;
  for (size_t i = 0; i < v.size(); ++i) {
    if (v[i] != std::floor(v[i])) throw errorAt(node_[key][i], fieldName(key), "expected whole numbers");
    out.push_back(static_cast<long>(v[i]));
  }
  return out;
}

YamlMap YamlMap::map(const std::string& key) {
  const YAML::Node n = required(key);
  if (!n.IsMap()) throw errorAt(n, fieldName(key), "expected a mapping of key: value pairs");
  if (Provenance* p = Provenance::active()) p->markSection(fieldName(key));
  return YamlMap(n, file_, fieldName(key));
}

std::optional<YamlMap> YamlMap::optionalMap(const std::string& key) {
  if (!has(key)) return std::nullopt;
  return map(key);
}

YamlMap YamlMap::mapOrEmpty(const std::string& key) {
  if (has(key)) return map(key);
  if (Provenance* p = Provenance::active()) p->markSection(fieldName(key));
  return YamlMap(YAML::Node(YAML::NodeType::Map), file_, fieldName(key));
}

std::vector<YamlMap> YamlMap::mapList(const std::string& key) {
  const YAML::Node n = required(key);
  if (!n.IsSequence()) throw errorAt(n, fieldName(key), "expected a list");
  std::vector<YamlMap> out;
  for (size_t i = 0; i < n.size(); ++i) {
    const std::string f = fieldName(key) + "[" + std::to_string(i) + "]";
    if (!n[i].IsMap()) throw errorAt(n[i], f, "expected a mapping of key: value pairs");
    if (Provenance* p = Provenance::active()) p->markSection(f);
    out.emplace_back(n[i], file_, f);
  }
  return out;
}

void YamlMap::finish() const {
  for (auto it = node_.begin(); it != node_.end(); ++it) {
    const std::string key = it->first.Scalar();
    if (std::find(declared_.begin(), declared_.end(), key) != declared_.end()) continue;
    const YAML::Mark m = it->first.Mark();
    if (key == "<<")  // YAML 1.1's merge key, which yaml-cpp reads as a key named "<<"
      throw ScenarioError(file_, m.line + 1, m.column + 1, fieldName(key),
                          "YAML merge keys ('<<: *anchor') are not supported: write the keys out, or give the whole "
                          "value as an alias ('key: *anchor'), or put the shared values in a base scenario (extends:)");
    const std::string near = closestMatch(key, declared_);
    std::string valid;
    for (const auto& d : declared_) valid += (valid.empty() ? "" : ", ") + d;
    throw ScenarioError(file_, m.line + 1, m.column + 1, fieldName(key),
                        "unknown key" + (near.empty() ? " (valid keys: " + valid + ")" : "; did you mean '" + near + "'?"));
  }
}

}  // namespace packsim
