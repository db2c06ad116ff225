// modelDescription.xml (FMI 2.0, co-simulation) from the variable table
// (core/fmu/fmu_variables.hpp), and the GUID that ties an FMU's description to the
// scenario its library loads from resources/.
#pragma once
#include <string>
#include <vector>

#include "core/fmu/fmu_variables.hpp"

namespace packsim {

constexpr const char* kFmuModelIdentifier = "packsim_fmu";  // binaries/linux64/<this>.so

// A GUID from the text of the scenario the FMU carries (FNV-1a over it and packsim's
// version): the library recomputes it at instantiation.
std::string fmuGuid(const std::string& scenarioText);

std::string modelDescriptionXml(const Scenario& s, const std::vector<FmuVariable>& vars, const std::string& guid);

}  // namespace packsim
