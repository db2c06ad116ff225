// The parts of packsim._packsim, one file each (module.cpp calls them in PYBIND11_MODULE),
// and the helpers they share.
#pragma once
#include <pybind11/pybind11.h>

#include <string>
#include <vector>

#include "core/scenario/overrides.hpp"
#include "core/scenario/scenario.hpp"

namespace packsim::python {

void bindCheck(pybind11::module_& m);  // check_bindings.cpp: `packsim check` as functions
void bindBatch(pybind11::module_& m);  // batch_bindings.cpp: sweeps and `packsim batch`
void bindBalance(pybind11::module_& m);  // balance_bindings.cpp: `packsim balance-time`
void bindFit(pybind11::module_& m);  // fit_bindings.cpp: `packsim fit`'s simulation (rc_response, simulate_cell)

// The scenario `run` and `balance_time` take (module.cpp): the file `source` if is_file,
// else YAML text named file_name whose relative paths resolve against base_dir; with the
// overrides applied. Call it with the GIL released.
Scenario loadScenarioSource(const std::string& source, bool is_file, const Overrides& overrides,
                            const std::string& file_name, const std::string& base_dir);

// f() with the GIL released (it must touch no Python object); its result, for the
// caller to convert once the GIL is back.
template <typename F>
auto withoutGil(F&& f) {
  pybind11::gil_scoped_release release;
  return f();
}

// [toPython(x) for x in v]
template <typename T, typename F>
pybind11::list listOf(const std::vector<T>& v, F&& toPython) {
  pybind11::list out;
  for (const T& x : v) out.append(toPython(x));
  return out;
}

}  // namespace packsim::python
