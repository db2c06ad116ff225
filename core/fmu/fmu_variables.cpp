#include "core/fmu/fmu_variables.hpp"

#include <algorithm>

#include "core/sim/bms_bridge.hpp"
#include "models/cell/curve.hpp"  // kZeroCelsius_K

namespace packsim {

namespace {


double cellTemp_K(const SimulationRun& r, int c) { return r.state()[r.plant().tempIndex(c)] + kZeroCelsius_K; }

double meanCellSoc(const SimulationRun& r) {
  const int n = r.plant().pack().cellCount();
  double sum = 0.0;
  for (int c = 0; c < n; ++c) sum += r.plant().cellStates(r.state(), c)[CellLayout::soc];
  return sum / n;
}

double cellTempExtreme_K(const SimulationRun& r, bool max) {
  double v = cellTemp_K(r, 0);
  for (int c = 1; c < r.plant().pack().cellCount(); ++c) v = max ? std::max(v, cellTemp_K(r, c)) : std::min(v, cellTemp_K(r, c));
  return v;
}

FmuVariable input(const char* name, FmuType type, const char* unit, FmuInput which, double start, const char* what) {
  FmuVariable v;
  v.name = name;
  v.type = type;
  v.causality = FmuCausality::Input;
  v.unit = unit;
  v.input = which;
  v.start = start;
  v.description = what;
  return v;
}

FmuVariable output(std::string name, FmuType type, const char* unit, std::string what,
                   std::function<double(const SimulationRun&)> get) {
  FmuVariable v;
  v.name = std::move(name);
  v.type = type;
  v.unit = unit;
  v.description = std::move(what);
  v.get = std::move(get);
  return v;
}

}  // namespace

const std::vector<FmuUnit>& fmuUnits() {
  static const std::vector<FmuUnit> units = {
      {"V", 1, 2, -3, -1, 0}, {"A", 0, 0, 0, 1, 0}, {"W", 1, 2, -3, 0, 0}, {"K", 0, 0, 0, 0, 1}};
  return units;
}

std::vector<FmuVariable> fmuVariables(const Scenario& s) {
  using T = FmuType;
  const bool powerLoad = s.load.quantity == LoadProfile::Quantity::Power_W;
  const double load0 = s.load.segmentAt(0.0).current_A(0.0);
  std::vector<FmuVariable> v = {
      input("load_current", T::Real, "A", FmuInput::LoadCurrent, powerLoad ? 0.0 : load0,
            "load current, positive discharges (scenarios with a current load; unset: the scenario's profile)"),
      input("load_power", T::Real, "W", FmuInput::LoadPower, powerLoad ? load0 : 0.0,
            "load power, positive discharges (scenarios with a power load; unset: the scenario's profile)"),
      input("ambient_temperature", T::Real, "K", FmuInput::Ambient, s.ambient_C.at(0.0) + kZeroCelsius_K,
            "ambient temperature (unset: the scenario's ambient)"),
      input("estop_internal", T::Boolean, "", FmuInput::EstopInternal, 0.0,
            "internal E-switch pulled (unset: the scenario's scripted E-switch faults)"),
      input("estop_external", T::Boolean, "", FmuInput::EstopExternal, 0.0,
            "external E-switch pulled (unset: the scenario's scripted E-switch faults)"),
      input("charger_present", T::Boolean, "", FmuInput::ChargerPresent, s.bms.charger_present ? 1.0 : 0.0,
            "charger-detect pin the BMS reads (unset: the scenario's bms.charger_present)"),
      output("pack_voltage", T::Real, "V", "pack terminal voltage", [](const SimulationRun& r) { return r.signals().pack_voltage_V; }),
      output("pack_current", T::Real, "A", "pack current, positive discharges",
             [](const SimulationRun& r) { return r.signals().pack_current_A; }),
      output("soc_true", T::Real, "", "true state of charge, mean over the cells (0..1)", meanCellSoc),
      output("soc_bms", T::Real, "", "the BMS's state-of-charge estimate (0..1)",
             [](const SimulationRun& r) { return r.outputs().telemetry.soc_permille * 1e-3; }),
      output("cell_temperature_min", T::Real, "K", "coldest cell", [](const SimulationRun& r) { return cellTempExtreme_K(r, false); }),
      output("cell_temperature_max", T::Real, "K", "hottest cell", [](const SimulationRun& r) { return cellTempExtreme_K(r, true); }),
      output("relay_closed", T::Boolean, "", "main relay contact closed (what the hardware did)",
             [](const SimulationRun& r) { return r.hardware().relay_closed ? 1.0 : 0.0; }),
      output("precharge_closed", T::Boolean, "", "precharge contact closed",
             [](const SimulationRun& r) { return r.hardware().precharge_closed ? 1.0 : 0.0; }),
      output("discharge_fet_on", T::Boolean, "", "discharge FET gate on (after the monitor's own FET control)",
             [](const SimulationRun& r) { return r.hardware().discharge_fet_on ? 1.0 : 0.0; }),
      output("charge_fet_on", T::Boolean, "", "charge FET gate on (after the monitor's own FET control)",
             [](const SimulationRun& r) { return r.hardware().charge_fet_on ? 1.0 : 0.0; }),
      output("fuse_blown", T::Boolean, "", "pack fuse blown", [](const SimulationRun& r) { return r.hardware().fuse_blown ? 1.0 : 0.0; }),
      output("monitor_fault_line", T::Boolean, "", "monitor FAULT / ALERT line asserted",
             [](const SimulationRun& r) { return r.hardware().fault_line ? 1.0 : 0.0; }),
      output("relay_command", T::Boolean, "", "the BMS commands the main relay closed",
             [](const SimulationRun& r) { return r.outputs().relayClose ? 1.0 : 0.0; }),
      output("bms_state", T::Integer, "", "BMS state (the number of bms::State, docs/results.md)",
             [](const SimulationRun& r) { return static_cast<double>(r.outputs().state); }),
      output("fault_active", T::Integer, "", "fault bits present and debounced (bit = bms::FaultId)",
             [](const SimulationRun& r) { return static_cast<double>(static_cast<int32_t>(r.outputs().faultActive)); }),
      output("fault_latched", T::Integer, "", "fault bits latched (bit = bms::FaultId)",
             [](const SimulationRun& r) { return static_cast<double>(static_cast<int32_t>(r.outputs().faultLatched)); }),
      output("tripped", T::Boolean, "", "the BMS opened the relay on a latched fault (stays true)",
             [](const SimulationRun& r) { return r.tripped() ? 1.0 : 0.0; }),
  };
  const int cells = s.pack.series * s.pack.parallel;
  for (int c = 0; c < cells; ++c) {
    const std::string n = "[" + std::to_string(c + 1) + "]";
    v.push_back(output("cell_voltage" + n, T::Real, "V", "terminal voltage of cell " + std::to_string(c + 1),
                       [c](const SimulationRun& r) { return r.signals().cell_voltage_V[static_cast<size_t>(c)]; }));
  }
  for (int c = 0; c < cells; ++c) {
    const std::string n = "[" + std::to_string(c + 1) + "]";
    v.push_back(output("cell_temperature" + n, T::Real, "K", "temperature of cell " + std::to_string(c + 1),
                       [c](const SimulationRun& r) { return cellTemp_K(r, c); }));
  }
  return v;
}

}  // namespace packsim
