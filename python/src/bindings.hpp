// The parts of packsim._packsim, one file each (module.cpp calls them in PYBIND11_MODULE).
#pragma once
#include <pybind11/pybind11.h>

namespace packsim::python {

void bindCheck(pybind11::module_& m);  // check_bindings.cpp: `packsim check` as functions
void bindBatch(pybind11::module_& m);  // batch_bindings.cpp: sweeps and `packsim batch`
void bindBalance(pybind11::module_& m);  // balance_bindings.cpp: `packsim balance-time`

}  // namespace packsim::python
