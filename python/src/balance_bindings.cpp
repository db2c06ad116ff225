// `packsim balance-time` for Python (core/balance/balance_time.hpp): time to balance per
// resistor, analytic and simulated. Options and rows cross as plain values and dicts;
// python/packsim/balance.py checks the arguments and formats the CLI's table.
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <optional>
#include <string>
#include <vector>

#include "core/balance/balance_table.hpp"
#include "core/balance/balance_time.hpp"
#include "core/cli/commands.hpp"
#include "python/src/bindings.hpp"

namespace py = pybind11;

namespace packsim::python {

namespace {

py::dict rowDict(const BalanceTimeRow& w) {
  py::dict d;
  d["resistor_ohm"] = w.resistor_ohm;
  d["branch_ohm"] = w.branch_ohm;
  d["current_A"] = w.current_A;
  d["power_W"] = w.power_W;
  d["board_power_W"] = w.board_power_W;
  d["resistor_W"] = w.resistor_W;
  d["within_rating"] = w.within_rating;
  d["const_I_all_h"] = w.const_I_all_h;
  d["const_I_to_target_h"] = w.const_I_to_target_h;
  d["droop_to_target_h"] = w.droop_to_target_h;
  d["board_steady_C"] = w.board_steady_C;
  d["simulated"] = w.simulated;
  d["firmware_h"] = w.firmware_h;
  d["firmware_note"] = w.firmware_note;
  d["true_h"] = w.true_h;
  d["end_reason"] = w.end_reason;
  d["peak_board_C"] = w.peak_board_C;
  d["board_peak_C"] = py::tuple(py::cast(w.board_peak_C));
  d["paused_fraction"] = w.paused_fraction;
  d["bled_Ah"] = w.bled_Ah;
  d["pack_useful_Ah"] = w.pack_useful_Ah;
  d["pack_wasted_Ah"] = w.pack_wasted_Ah;
  d["needed_Ah"] = w.needed_Ah;
  d["pack_heat_Wh"] = w.pack_heat_Wh;
  d["final_spread_Ah"] = w.final_spread_Ah;
  d["final_imbalance_Ah"] = w.final_imbalance_Ah;
  d["tripped"] = w.tripped;
  d["within_limits"] = w.within_limits;
  d["fastest"] = w.fastest;
  d["charge_h"] = w.charge_h;
  d["charge_without_h"] = w.charge_without_h;
  d["charge_added_h"] = w.charge_added_h;
  return d;
}

}  // namespace

void bindBalance(py::module_& m) {
  m.def(
      "balance_time",
      [](const std::string& source, bool is_file, const Overrides& overrides, const std::vector<double>& resistors_ohm,
         std::optional<double> delta_Ah, std::optional<double> cell_V, int high_cells, std::optional<double> target_mV,
         double max_hours, bool simulate, std::optional<std::string> when, bool during_charge,
         const std::string& file_name, const std::string& base_dir) {
        BalanceTimeOptions opt;
        opt.resistors_ohm = resistors_ohm;
        opt.delta_Ah = delta_Ah;
        opt.cell_V = cell_V;
        opt.high_cells = high_cells;
        opt.target_mV = target_mV;
        opt.max_hours = max_hours;
        opt.simulate = simulate;
        opt.when = when;
        opt.during_charge = during_charge;
        const BalanceTimeResult r = withoutGil(
            [&] { return balanceTime(loadScenarioSource(source, is_file, overrides, file_name, base_dir), opt); });
        py::dict d;
        d["scenario"] = r.scenario;
        d["delta_Ah"] = r.delta_Ah;
        d["cell_V"] = r.cell_V;
        d["high_cells"] = r.high_cells;
        d["delta_given"] = r.delta_given;
        d["target_mV"] = r.target_mV;
        d["resistor_rating_W"] = r.resistor_rating_W;
        d["board_max_C"] = r.board_max_C;
        d["when"] = r.when;
        d["when_overridden"] = r.when_overridden;
        d["during_charge"] = r.during_charge;
        d["warnings"] = py::tuple(py::cast(r.warnings));
        d["text"] = balanceTimeTable(r);
        d["rows"] = listOf(r.rows, rowDict);
        return d;
      },
      py::arg("source"), py::arg("is_file"), py::arg("overrides"), py::arg("resistors_ohm"), py::arg("delta_Ah"),
      py::arg("cell_V"), py::arg("high_cells"), py::arg("target_mV"), py::arg("max_hours"), py::arg("simulate"),
      py::arg("when"), py::arg("during_charge"),
      py::arg("file_name") = "<scenario>", py::arg("base_dir") = ".",
      "Time to balance per resistor as `packsim balance-time` (GIL released): a scenario file (is_file) or YAML "
      "text with (dotted key, YAML value) overrides; a dict {scenario, delta_Ah, delta_given, cell_V, high_cells, target_mV, "
      "resistor_rating_W, board_max_C, when, when_overridden, during_charge, warnings, text, rows}. A bad option raises ValueError.");
  m.def("preset_path", &presetPath, py::arg("name"),
        "Path of a bundled scenario by name (scenarios/NAME.yaml or scenarios/balance/NAME.yaml), as "
        "`packsim balance-time --preset NAME`; ValueError listing the names if there is none.");
}

}  // namespace packsim::python
