// What looks wrong in a scenario that loads: one table of checks, each a small
// function naming the key(s) and where each came from (docs/scenario.md "Warnings").
// `packsim show` prints them; `packsim run` prints them to stderr and records each as a
// `config_warning` event at t = 0.
#pragma once
#include <yaml-cpp/yaml.h>

#include <string>
#include <vector>

#include "core/scenario/scenario.hpp"

namespace packsim {

class Provenance;

// Every cell should be within this many cell-to-cell conductances of a cell with a
// thermistor: one thermistor watches up to nine neighbouring cells (4 either side), what
// a three-input AFE gives a 16s pack (cells 1, 8, 16). Further away a hot cell reaches a
// thermistor only through several conductances, minutes late and kelvins low. The cells
// are linked in storage order (a group's parallel cells one after the other), and a
// thermistor sits on its group's first cell.
constexpr int kThermistorReachLinks = 4;
// Fewer links where the conductances are weak against each cell's own losses: a cell
// counts as watched only if, even at steady state, its temperature rise lifts the
// thermistor's cell by at least this fraction of it (a cell 75 K above ambient that moves
// its thermistor by under 7.5 K reads as a normal cell).
constexpr double kThermistorSeenFraction = 0.1;

// The links within which a hot cell is watched: kThermistorReachLinks, or fewer where a
// hot cell's steady rise falls below kThermistorSeenFraction sooner along the chain of
// cell-to-cell conductances (0 when they are 0: each thermistor sees only its own cell).
int thermistorReachLinks(const Scenario& s);
// A load above these C-rates per cell is implausible for the pack when its cell states
// no max_discharge_C / max_charge_C (often a unit slip: mA or W read as A).
constexpr double kImplausibleDischargeC = 20.0;
constexpr double kImplausibleChargeC = 10.0;
// An over-current limit above this fraction of the current sensor's range is "close".
constexpr double kLimitNearSensorRange = 0.9;

struct WarningCheck {
  const char* name;
  void (*check)(const Scenario& s, const Provenance& p, std::vector<std::string>& out);
};
const std::vector<WarningCheck>& warningChecks();

// The load's own warnings (an override that removed a dependence, a derived default)
// followed by every check's.
std::vector<std::string> scenarioWarnings(const Scenario& s);

// A curve of the cell preset that depended on SOC (or charge) or temperature and no
// longer does after the scenario's field overrides: one warning each, on `prov`. An
// override written as a curve of its own (a mapping in `given`, the scenario's cell
// node: `{poly: [0.03], arrhenius_K: 0}`) states its dependences deliberately and is
// not warned about; a plain number is.
void presetDependenceWarnings(const std::string& cellKey, const CellParams& preset, const CellParams& cell,
                              const YAML::Node& given,
                              const std::string& presetName, Provenance& prov);

// "file:line" of a node (just "file" when the node has no position).
std::string nodePlace(const std::string& file, const YAML::Node& n);
// `key`'s table or list at `beforeWhere` replaced by the single value `after` at `afterWhere`.
std::string dependenceRemovedWarning(const std::string& key, const YAML::Node& before, const std::string& beforeWhere,
                                     const YAML::Node& after, const std::string& afterWhere);

}  // namespace packsim
