// One run's C++ scenario and result, and their recorded arrays as NumPy views.
#pragma once
#include <pybind11/pybind11.h>

#include "core/scenario/scenario.hpp"
#include "core/sim/result.hpp"

namespace packsim::python {

struct RunHandle {
  Scenario scenario;
  RunResult result;
};

// {HDF5 dataset path ("time_s", "truth/cell_voltage_V", ...): read-only numpy array}
// viewing the vectors of handle.result.rec without copying; each array keeps the
// handle alive: every channel of the result-channel table (core/sim/result_channels.hpp)
// the run recorded, with the paths, shapes and dtypes core/io/hdf5_writer.cpp writes.
pybind11::dict recordingArrays(pybind11::object handle);

// The result-channel table as [{path, units, axis, dtype, long_name}] (docs test).
pybind11::list resultChannelTable();

}  // namespace packsim::python
