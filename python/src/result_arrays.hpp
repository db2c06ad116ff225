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
// handle alive. Paths, shapes and dtypes are those core/io/hdf5_writer.cpp writes;
// datasets missing here are read from the written file by the Python layer, so a new
// dataset shows up in packsim.run results even before it is listed here.
pybind11::dict recordingArrays(pybind11::object handle);

}  // namespace packsim::python
