#include "core/scenario/bms_setting_table.hpp"

#include <bms/bms_settings.hpp>
#include <sstream>
#include <stdexcept>

#include "core/scenario/provenance.hpp"

namespace packsim {

namespace {

std::vector<std::string> words(const char* names) {
  std::vector<std::string> out;
  std::istringstream is(names);
  for (std::string w; is >> w;) out.push_back(w);
  return out;
}

std::vector<SettingRow> makeRows() {
  using K = SettingKind;
  std::vector<SettingRow> rows;
  // clang-format off
#define BMS_NUMBER(key, field, unit, fwUnit, mul, div, def, lo, hi, loOpen, doc)                              \
  rows.push_back({key, K::Number, unit, fwUnit, mul, div, def, lo, hi, loOpen, {}, doc,                      \
                  [](bms::Config& c, double v) { bms::setSetting(c.field, v * (mul) / (div)); },            \
                  [](const bms::Config& c) { return static_cast<double>(c.field); }});
#define BMS_INTEGER(key, field, unit, def, lo, hi, doc)                                                      \
  rows.push_back({key, K::Integer, unit, unit, 1.0, 1.0, def, lo, hi, false, {}, doc,                        \
                  [](bms::Config& c, double v) { bms::setSetting(c.field, v); },                             \
                  [](const bms::Config& c) { return static_cast<double>(c.field); }});
#define BMS_FLAG(key, field, def, doc)                                                                       \
  rows.push_back({key, K::Flag, "", "", 1.0, 1.0, (def) ? 1.0 : 0.0, 0.0, 1.0, false, {}, doc,              \
                  [](bms::Config& c, double v) { c.field = v != 0.0; },                                      \
                  [](const bms::Config& c) { return c.field ? 1.0 : 0.0; }});
#define BMS_ENABLE(key, field, doc)                                                                          \
  rows.push_back({key, K::Enable, "", "", 1.0, 1.0, 0.0, 0.0, 1.0, false, {}, doc,                           \
                  [](bms::Config& c, double v) { c.field = v != 0.0; },                                      \
                  [](const bms::Config& c) { return c.field ? 1.0 : 0.0; }});
#define BMS_CHOICE(key, field, def, names, doc)                                                              \
  rows.push_back({key, K::Choice, "", "", 1.0, 1.0, static_cast<double>(static_cast<int>(def)), 0.0,        \
                  static_cast<double>(words(names).size() - 1), false, words(names), doc,                    \
                  [](bms::Config& c, double v) { bms::setSetting(c.field, v); },                             \
                  [](const bms::Config& c) { return static_cast<double>(static_cast<int>(c.field)); }});
#include <bms/bms_settings.def>
#undef BMS_NUMBER
#undef BMS_INTEGER
#undef BMS_FLAG
#undef BMS_ENABLE
#undef BMS_CHOICE
  // clang-format on
  return rows;
}

std::string num(double v) { return numberText(v); }

}  // namespace

std::string SettingRow::section() const {
  const std::string k = key;
  const size_t dot = k.rfind('.');
  return dot == std::string::npos ? "" : k.substr(0, dot);
}

std::string SettingRow::leaf() const {
  const std::string k = key;
  const size_t dot = k.rfind('.');
  return dot == std::string::npos ? k : k.substr(dot + 1);
}

std::string SettingRow::defaultText() const {
  switch (kind) {
    case SettingKind::Flag:
    case SettingKind::Enable: return def != 0.0 ? "true" : "false";
    case SettingKind::Choice: return choices[static_cast<size_t>(def)];
    case SettingKind::Integer: return std::to_string(static_cast<long>(def));
    case SettingKind::Number: break;
  }
  return num(def);
}

std::string SettingRow::rangeText() const {
  switch (kind) {
    case SettingKind::Flag:
    case SettingKind::Enable: return "true \\| false";
    case SettingKind::Choice: {
      std::string out;
      for (size_t i = 0; i < choices.size(); ++i) out += (i ? " \\| " : "") + ("`" + choices[i] + "`");
      return out;
    }
    case SettingKind::Integer: return "[" + num(lo) + ", " + num(hi) + "]";
    case SettingKind::Number: break;
  }
  return Range(lo, hi, loOpen, false).describe();
}

const std::vector<SettingRow>& settingRows() {
  static const std::vector<SettingRow> rows = makeRows();
  return rows;
}

const SettingRow& settingRow(const std::string& key) {
  for (const SettingRow& r : settingRows())
    if (key == r.key) return r;
  throw std::out_of_range("no BMS setting '" + key + "' (bms/bms_settings.def)");
}

std::map<std::string, double> readSettings(YamlMap* m, const std::string& section, bms::Config& image) {
  std::map<std::string, double> values;
  for (const SettingRow& r : settingRows()) {
    if (r.section() != section) continue;
    const std::string leaf = r.leaf();
    double v = r.def;
    if (m == nullptr) {
      // Not stated: the firmware's default, listed by `show` as one.
      if (Provenance* p = Provenance::active())
        p->recordDefault("bms." + r.section() + (section.empty() ? "" : ".") + leaf, r.defaultText());
    } else {
      switch (r.kind) {
        case SettingKind::Number: v = m->number(leaf, r.def, Range(r.lo, r.hi, r.loOpen, false)); break;
        case SettingKind::Integer:
          v = static_cast<double>(m->integer(leaf, static_cast<long>(r.def), static_cast<long>(r.lo), static_cast<long>(r.hi)));
          break;
        case SettingKind::Flag: v = m->boolean(leaf, r.def != 0.0) ? 1.0 : 0.0; break;
        case SettingKind::Enable: v = m->boolean(leaf, true) ? 1.0 : 0.0; break;  // stating the section turns it on
        case SettingKind::Choice: {
          const std::string name = m->choice(leaf, r.choices[static_cast<size_t>(r.def)], r.choices);
          v = static_cast<double>(settingChoiceIndex(r.key, name));
          break;
        }
      }
    }
    r.set(image, v);
    values[leaf] = v;
  }
  return values;
}

int settingChoiceIndex(const std::string& key, const std::string& name) {
  const std::vector<std::string>& c = settingRow(key).choices;
  for (size_t i = 0; i < c.size(); ++i)
    if (c[i] == name) return static_cast<int>(i);
  return -1;
}

std::string settingChoice(const std::string& key, const bms::Config& image) {
  const SettingRow& r = settingRow(key);
  return r.choices.at(static_cast<size_t>(r.get(image)));
}

double settingValue(const std::string& key, const bms::Config& image) {
  const SettingRow& r = settingRow(key);
  return r.get(image) * r.div / r.mul;
}

std::string settingsDocTable() {
  std::ostringstream os;
  os << "| key | default | range | unit | firmware unit | meaning |\n|---|---|---|---|---|---|\n";
  for (const SettingRow& r : settingRows()) {
    const bool yesNo = r.kind == SettingKind::Flag || r.kind == SettingKind::Enable;
    const std::string fw = yesNo ? "bool" : r.kind == SettingKind::Choice ? "enum" : r.fwUnit[0] ? r.fwUnit : "count";
    os << "| `bms." << r.key << "` | " << r.defaultText() << (r.kind == SettingKind::Enable ? " (true once the section is stated)" : "")
       << " | " << r.rangeText() << " | " << r.unit << " | " << fw << " | " << r.doc << " |\n";
  }
  return os.str();
}

}  // namespace packsim
