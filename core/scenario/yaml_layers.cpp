#include "core/scenario/yaml_layers.hpp"

#include <initializer_list>

namespace packsim {

namespace {

bool hasAny(const YAML::Node& m, std::initializer_list<const char*> keys) {
  for (const char* k : keys)
    if (m[k]) return true;
  return false;
}

void removeAll(YAML::Node m, std::initializer_list<const char*> keys) {
  for (const char* k : keys) m.remove(k);
}

// Sections whose keys are a choice of exactly one (the loader refuses both).
struct Choice {
  const char* path;
  const char* a;
  const char* b;
};
constexpr Choice kChoices[] = {{"ambient", "temp_C", "profile"}, {"hardware.thermistors", "at_groups", "channels"}};

}  // namespace

bool removesKey(const YAML::Node& value) { return value.IsDefined() && value.IsNull(); }

bool isCurveMapping(const YAML::Node& n) { return n.IsDefined() && n.IsMap() && hasAny(n, {"poly", "x", "y"}); }

void dropReplacedAlternatives(YAML::Node base, const YAML::Node& layer, const std::string& path) {
  if (!base.IsMap() || !layer.IsMap()) return;
  const YAML::Node& cbase = base;  // const: lookups must not add keys
  const YAML::Node& clayer = layer;
  if (isCurveMapping(cbase)) {
    // A layer that states the curve's form (`poly`, or an `x` grid) gives the curve as
    // written: the base's form and axis do not carry over (a SOC grid read on the base's
    // discharged_Ah axis would be a wrong curve that loads).
    if (hasAny(clayer, {"poly", "x"})) removeAll(base, {"poly", "x", "y", "axis"});
    if (clayer["temp_C"]) removeAll(base, {"arrhenius_K", "ref_temp_C"});
    if (hasAny(clayer, {"arrhenius_K", "ref_temp_C"})) removeAll(base, {"temp_C"});
  }
  for (const Choice& c : kChoices) {
    if (path != c.path) continue;
    if (clayer[c.a]) base.remove(c.b);
    if (clayer[c.b]) base.remove(c.a);
  }
}

}  // namespace packsim
