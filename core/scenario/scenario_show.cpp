#include "core/scenario/scenario_show.hpp"

#include <algorithm>
#include <cstdio>
#include <sstream>

#include "core/scenario/provenance.hpp"

namespace packsim {

namespace {

const Provenance& provenanceOf(const Scenario& s) {
  static const Provenance none("");
  return s.provenance ? *s.provenance : none;
}

// One step of a dotted key: "pack", "faults", "[0]".
std::vector<std::string> splitKey(const std::string& key) {
  std::vector<std::string> steps;
  std::string cur;
  for (char c : key) {
    if (c == '.' || c == '[') {
      if (!cur.empty()) steps.push_back(cur);
      cur = c == '[' ? "[" : "";
    } else {
      cur += c;
    }
  }
  if (!cur.empty()) steps.push_back(cur);
  return steps;
}

// The section a key is shown under: its first step ("" for top-level values).
std::string sectionOf(const std::string& key) {
  const std::vector<std::string> steps = splitKey(key);
  return steps.size() > 1 ? steps.front() : "";
}

struct TreeNode {
  std::string step;  // "name" or "[i]"
  std::string path;  // dotted key up to here
  const ProvenanceEntry* leaf = nullptr;
  std::vector<TreeNode> kids;
  bool hasStated() const {
    if (leaf) return leaf->stated;
    return std::any_of(kids.begin(), kids.end(), [](const TreeNode& k) { return k.hasStated(); });
  }
};

void insert(TreeNode& root, const ProvenanceEntry& e) {
  TreeNode* cur = &root;
  for (const std::string& step : splitKey(e.key)) {
    auto it = std::find_if(cur->kids.begin(), cur->kids.end(), [&](const TreeNode& k) { return k.step == step; });
    if (it == cur->kids.end()) {
      TreeNode n;
      n.step = step;
      n.path = cur->path.empty() ? step : (step[0] == '[' ? cur->path + step : cur->path + "." + step);
      cur->kids.push_back(n);
      it = cur->kids.end() - 1;
    }
    cur = &*it;
  }
  cur->leaf = &e;
}

// A value whose text spans lines (a long description) as one YAML line.
std::string oneLine(const std::string& v) {
  if (v.find('\n') == std::string::npos) return v;
  std::string out = "\"";
  for (char c : v) {
    if (c == '\n') out += "\\n";
    else if (c == '"' || c == '\\') out += std::string("\\") + c;
    else out += c;
  }
  return out + "\"";
}

void emitYaml(const TreeNode& n, const Provenance& p, int indent, bool commented, std::ostringstream& os) {
  for (const TreeNode& k : n.kids) {
    const bool isIndex = k.step[0] == '[';
    const std::string pad(static_cast<size_t>(indent), ' ');
    const std::string name = isIndex ? "-" : k.step + ":";
    if (k.leaf) {
      const bool off = commented || !k.leaf->stated;
      os << pad << (off ? "# " : "") << name << " " << oneLine(k.leaf->value) << "  # " << k.leaf->origin << "\n";
      continue;
    }
    const bool off = commented || !(k.hasStated() || p.sectionPresent(k.path));
    if (!k.hasStated() && !off) {
      os << pad << name << " {}\n";  // present with every value a default (e.g. `fuse: {}`)
      TreeNode copy = k;
      emitYaml(copy, p, indent + 2, true, os);
      continue;
    }
    os << pad << (off ? "# " : "") << name << "\n";
    emitYaml(k, p, indent + 2, off, os);
  }
}

std::string jsonString(const std::string& v) {
  std::string out = "\"";
  for (unsigned char c : v) {
    switch (c) {
      case '"': out += "\\\""; break;
      case '\\': out += "\\\\"; break;
      case '\n': out += "\\n"; break;
      case '\t': out += "\\t"; break;
      case '\r': out += "\\r"; break;
      default:
        if (c < 0x20) {
          char buf[8];
          std::snprintf(buf, sizeof buf, "\\u%04x", c);
          out += buf;
        } else {
          out += static_cast<char>(c);
        }
    }
  }
  return out + "\"";
}

std::string shortened(const std::string& v, size_t max) {
  const std::string one = oneLine(v);
  if (one.size() <= max) return one;
  return one.substr(0, max - 4) + " ...";
}

}  // namespace

std::string showText(const Scenario& s) {
  const Provenance& p = provenanceOf(s);
  const std::vector<ProvenanceEntry> entries = p.entries();
  // Sections in their first appearance; within one, keys in reading order.
  std::vector<std::string> sections;
  for (const ProvenanceEntry& e : entries) {
    const std::string sec = sectionOf(e.key);
    if (std::find(sections.begin(), sections.end(), sec) == sections.end()) sections.push_back(sec);
  }
  size_t keyWidth = 0, valueWidth = 0;
  constexpr size_t kMaxValue = 48;
  for (const ProvenanceEntry& e : entries) {
    keyWidth = std::max(keyWidth, e.key.size() - sectionOf(e.key).size());
    valueWidth = std::max(valueWidth, std::min(kMaxValue, shortened(e.value, kMaxValue).size()));
  }
  std::ostringstream os;
  os << "scenario  " << (s.file.empty() ? "<text>" : s.file) << "  (" << s.name << ")\n";
  for (const std::string& sec : sections) {
    os << "\n" << (sec.empty() ? "scenario" : sec) << "\n";
    for (const ProvenanceEntry& e : entries) {
      if (sectionOf(e.key) != sec) continue;
      std::string rest = e.key.substr(sec.size());
      if (!rest.empty() && rest[0] == '.') rest = rest.substr(1);
      if (rest.empty()) rest = "(value)";
      const std::string v = shortened(e.value, kMaxValue);
      os << "  " << rest << std::string(keyWidth + 2 - std::min(keyWidth + 1, rest.size()), ' ') << v
         << std::string(valueWidth + 2 - std::min(valueWidth + 1, v.size()), ' ') << e.origin << "\n";
    }
  }
  os << "\n";
  if (s.warnings.empty()) {
    os << "warnings  none\n";
  } else {
    os << "warnings  " << s.warnings.size() << "\n";
    for (const std::string& w : s.warnings) os << "  - " << w << "\n";
  }
  return os.str();
}

std::string showYaml(const Scenario& s) {
  const Provenance& p = provenanceOf(s);
  const std::vector<ProvenanceEntry> entries = p.entries();
  TreeNode root;
  for (const ProvenanceEntry& e : entries) insert(root, e);
  std::ostringstream os;
  os << "# packsim show " << (s.file.empty() ? "<text>" : s.file) << ": the scenario after presets, extends, --set\n"
     << "# and defaults. Keys are what the files and --set state (origin after '#'); commented-out\n"
     << "# lines are preset values and defaults, which the loader takes again when this runs.\n";
  for (const std::string& w : s.warnings) os << "# warning: " << oneLine(w) << "\n";
  emitYaml(root, p, 0, false, os);
  return os.str();
}

std::string showJson(const Scenario& s) {
  const Provenance& p = provenanceOf(s);
  std::ostringstream os;
  os << "{\n  \"scenario\": " << jsonString(s.file) << ",\n  \"values\": {";
  bool first = true;
  for (const ProvenanceEntry& e : p.entries()) {
    os << (first ? "\n" : ",\n") << "    " << jsonString(e.key) << ": {\"value\": " << jsonString(e.value)
       << ", \"origin\": " << jsonString(e.origin) << ", \"stated\": " << (e.stated ? "true" : "false") << "}";
    first = false;
  }
  os << "\n  },\n  \"warnings\": [";
  first = true;
  for (const std::string& w : s.warnings) {
    os << (first ? "\n" : ",\n") << "    " << jsonString(w);
    first = false;
  }
  os << "\n  ]\n}\n";
  return os.str();
}

}  // namespace packsim
