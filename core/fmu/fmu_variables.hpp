// The FMU's variables as one table. `packsim fmu` writes modelDescription.xml from it
// and the FMU library (fmu_api.cpp) resolves value references with it: a variable's
// value reference is its row, so the two cannot drift. The table depends on the
// scenario only through its sizes (cells) and the inputs' start values.
//
// Units: SI with temperatures in K (FMI convention); current positive discharges.
// Outputs are what the last BMS tick sampled and did at the communication point.
#pragma once
#include <functional>
#include <string>
#include <vector>

#include "core/scenario/scenario.hpp"
#include "core/sim/simulation.hpp"

namespace packsim {

enum class FmuType { Real, Integer, Boolean };
enum class FmuCausality { Input, Output };
// Which external input a row sets (core/sim/external_inputs.hpp).
enum class FmuInput { None, LoadCurrent, LoadPower, Ambient, EstopInternal, EstopExternal, ChargerPresent };

struct FmuVariable {
  std::string name;
  FmuType type = FmuType::Real;
  FmuCausality causality = FmuCausality::Output;
  std::string unit;  // a unit of fmuUnits(), or "" for a plain number
  std::string description;
  FmuInput input = FmuInput::None;
  double start = 0.0;                               // inputs: the scenario's own value at t = 0
  std::function<double(const SimulationRun&)> get;  // outputs (Integer / Boolean as a double)
};

// Value reference = index in the returned vector.
std::vector<FmuVariable> fmuVariables(const Scenario& s);

// The units the table uses: name and SI base-unit exponents (V = kg·m²·s⁻³·A⁻¹).
struct FmuUnit {
  const char* name;
  int kg, m, s, A, K;
};
const std::vector<FmuUnit>& fmuUnits();

}  // namespace packsim
