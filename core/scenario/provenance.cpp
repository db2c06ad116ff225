#include "core/scenario/provenance.hpp"

#include <algorithm>
#include <charconv>
#include <filesystem>
#include <vector>

#include "core/scenario/decimal_text.hpp"

namespace packsim {

namespace {
thread_local Provenance* tActive = nullptr;
}

Provenance* Provenance::active() { return tActive; }

Provenance::Scope::Scope(Provenance* p) : previous_(tActive) { tActive = p; }
Provenance::Scope::~Scope() { tActive = previous_; }

std::string Provenance::displayName(const std::string& path) {
  return std::filesystem::path(path).lexically_normal().string();
}

bool keyUnder(const std::string& inner, const std::string& outer) {
  if (outer.empty()) return true;
  if (inner.size() < outer.size() || inner.compare(0, outer.size(), outer) != 0) return false;
  return inner.size() == outer.size() || inner[outer.size()] == '.' || inner[outer.size()] == '[';
}

std::string numberText(double v) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

namespace {

// A scalar the Emitter writes as it stands (plain, no tag): a number -?D+(.D*)?([eE][-+]?D+)?
// (D: a digit), untagged or quoted in the source (its tag "?" or "!").
bool plainNumber(const YAML::Node& n) {
  return n.IsScalar() && (n.Tag() == "?" || n.Tag() == "!") && decimalText(n.Scalar(), false);
}

// yamlFlowText of a list of such numbers (a curve's points, a load profile's times:
// often hundreds), "[a, b, c]" as the Emitter writes it, without the Emitter's scans of
// every character (some 16,000 instructions a value). False for anything else -- another
// kind of node or value, a tag on the list, a value that is in it twice (an alias: the
// Emitter writes an anchor) -- which the Emitter then writes.
bool numberListText(const YAML::Node& n, std::string& text) {
  if (!n.IsSequence() || n.Tag() != "?") return false;
  std::vector<const std::string*> values;  // each value's node, by its text's address
  values.reserve(n.size());
  for (const YAML::Node& v : n) {
    if (!plainNumber(v)) return false;
    values.push_back(&v.Scalar());
  }
  std::vector<const std::string*> sorted = values;
  std::sort(sorted.begin(), sorted.end());
  if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end()) return false;
  text = "[";
  for (size_t i = 0; i < values.size(); ++i) (i ? text += ", " : text) += *values[i];
  text += "]";
  return true;
}

}  // namespace

std::string yamlFlowText(const YAML::Node& n) {
  if (std::string text; numberListText(n, text)) return text;
  YAML::Emitter out;
  out.SetMapFormat(YAML::Flow);
  out.SetSeqFormat(YAML::Flow);
  out << n;
  return out.c_str();
}

void Provenance::resetFiles(const std::string& file) {
  files_.clear();
  files_[""] = displayName(file);
}

void Provenance::eraseUnder(const std::string& path) {
  for (auto it = files_.begin(); it != files_.end();)
    it = (!path.empty() && keyUnder(it->first, path)) ? files_.erase(it) : std::next(it);
}

void Provenance::setFile(const std::string& path, const std::string& file) {
  eraseUnder(path);
  files_[path] = displayName(file);
}

std::string Provenance::fileOf(const std::string& key) const {
  std::string file = top_;
  size_t best = 0;
  for (const auto& [path, f] : files_) {
    if (keyUnder(key, path) && path.size() >= best) {
      best = path.size();
      file = f;
    }
  }
  return file;
}

void Provenance::addOverride(const std::string& field, const std::string& text) { overrides_.emplace_back(field, text); }

bool Provenance::overridden(const std::string& key) const {
  for (const auto& o : overrides_)
    if (keyUnder(key, o.first)) return true;
  return false;
}

void Provenance::addPresetScope(const std::string& path, const std::string& name, const std::string& file,
                                const std::vector<std::string>& scenarioKeys) {
  presets_.push_back({path, name, std::filesystem::path(file).filename().string(), scenarioKeys});
}

const Provenance::PresetScope* Provenance::presetFor(const std::string& key) const {
  for (auto p = presets_.rbegin(); p != presets_.rend(); ++p) {
    if (!keyUnder(key, p->path) || key == p->path) continue;
    // A scenario key is a field (`r0_ohm`) or a part of a curve given in part (`ocv_V.y`).
    const std::string rest = key.substr(p->path.size() + 1);
    for (const std::string& given : p->scenarioKeys)
      if (keyUnder(rest, given)) return nullptr;
    return &*p;
  }
  return nullptr;
}

std::string Provenance::originFor(const std::string& key, const YAML::Node& n, bool& stated) const {
  const int line = n.Mark().line >= 0 ? n.Mark().line + 1 : 0;
  const std::string at = line > 0 ? ":" + std::to_string(line) : "";
  if (const PresetScope* p = presetFor(key)) {
    stated = false;
    return "preset " + p->name + " (" + p->file + at + ")";
  }
  const std::string file = fileOf(key);
  stated = true;
  if (file == top_) {
    for (auto o = overrides_.rbegin(); o != overrides_.rend(); ++o)
      if (keyUnder(key, o->first)) return "--set " + o->second;
  }
  return file + at;
}

void Provenance::put(ProvenanceEntry e) {
  // A raw list or mapping recorded at a key the loader then descends into gives way
  // to the values inside it.
  for (size_t i = 1; i < e.key.size(); ++i) {
    if (e.key[i] != '.' && e.key[i] != '[') continue;
    const auto parent = index_.find(e.key.substr(0, i));
    if (parent != index_.end()) alive_[parent->second] = false;
  }
  const auto it = index_.find(e.key);
  if (it != index_.end()) {
    entries_[it->second] = std::move(e);
    alive_[it->second] = true;
    return;
  }
  index_[e.key] = entries_.size();
  entries_.push_back(std::move(e));
  alive_.push_back(true);
}

void Provenance::recordNode(const std::string& key, const YAML::Node& n) {
  if (!n.IsDefined()) return;
  ProvenanceEntry e;
  e.key = key;
  e.value = yamlFlowText(n);
  e.origin = originFor(key, n, e.stated);
  put(std::move(e));
}

void Provenance::recordDefault(const std::string& key, const std::string& valueYaml, const std::string& origin) {
  ProvenanceEntry e;
  e.key = key;
  e.value = valueYaml;
  e.origin = origin;
  e.stated = false;
  put(std::move(e));
}

void Provenance::warn(const std::string& text) {
  if (std::find(warnings_.begin(), warnings_.end(), text) == warnings_.end()) warnings_.push_back(text);
}

std::vector<ProvenanceEntry> Provenance::entries() const {
  std::vector<ProvenanceEntry> out;
  for (size_t i = 0; i < entries_.size(); ++i)
    if (alive_[i]) out.push_back(entries_[i]);
  return out;
}

const ProvenanceEntry* Provenance::find(const std::string& key) const {
  const auto it = index_.find(key);
  return it == index_.end() || !alive_[it->second] ? nullptr : &entries_[it->second];
}

std::string Provenance::originOf(const std::string& key) const {
  const ProvenanceEntry* e = find(key);
  return e ? e->origin : "default";
}

std::string Provenance::describe(const std::string& key, const std::string& fallbackValue) const {
  const ProvenanceEntry* e = find(key);
  const std::string v = e ? e->value : fallbackValue;
  return key + (v.empty() ? "" : " = " + v) + " (" + (e ? e->origin : "default") + ")";
}

}  // namespace packsim
