#include <iostream>
#include <stdexcept>

#include "core/cli/commands.hpp"
#include "core/scenario/overrides.hpp"
#include "core/scenario/scenario_show.hpp"

namespace packsim {

int cmdShow(const ShowOptions& o) {
  const Scenario s = loadScenarioFileWithOverrides(scenarioArgPath(o.scenario), parseSetOptions(o.set));
  if (o.format == "yaml") std::cout << showYaml(s);
  else if (o.format == "json") std::cout << showJson(s);
  else if (o.format == "text" || o.format.empty()) std::cout << showText(s);
  else throw std::invalid_argument("--format " + o.format + ": expected text, yaml or json");
  return 0;
}

}  // namespace packsim
