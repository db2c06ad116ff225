#include "python/src/result_arrays.hpp"

#include <pybind11/numpy.h>

#include <stdexcept>
#include <string>
#include <vector>

namespace py = pybind11;

namespace packsim::python {

namespace {

// A read-only view of v as [rows] (cols == 0) or [rows, cols], owned by `owner`.
// Strides are given explicitly (pybind11 2.10's default strides read the dtype's
// itemsize through a struct layout NumPy 2 changed).
template <typename T>
py::array view(const std::vector<T>& v, size_t rows, size_t cols, const py::object& owner, const char* path) {
  const size_t expected = cols == 0 ? rows : rows * cols;
  if (v.size() != expected)
    throw std::logic_error(std::string("recording ") + path + " holds " + std::to_string(v.size()) +
                           " values, expected " + std::to_string(expected));
  std::vector<py::ssize_t> shape{static_cast<py::ssize_t>(rows)};
  std::vector<py::ssize_t> strides{static_cast<py::ssize_t>(sizeof(T))};
  if (cols != 0) {
    shape.push_back(static_cast<py::ssize_t>(cols));
    strides = {static_cast<py::ssize_t>(cols * sizeof(T)), static_cast<py::ssize_t>(sizeof(T))};
  }
  static const T empty{};
  py::array a(py::dtype::of<T>(), shape, strides, v.empty() ? &empty : v.data(), owner);
  a.attr("setflags")(py::arg("write") = false);
  return a;
}

}  // namespace

py::dict recordingArrays(py::object handle) {
  const RunHandle& h = handle.cast<const RunHandle&>();
  const Recording& r = h.result.rec;
  const size_t n = r.samples();
  const auto cells = static_cast<size_t>(r.cells);
  const auto groups = static_cast<size_t>(r.groups);
  const auto therm = static_cast<size_t>(r.thermistors);
  py::dict d;
  auto put = [&](const char* path, const auto& vec, size_t cols) { d[path] = view(vec, n, cols, handle, path); };
  put("time_s", r.time_s, 0);
  put("truth/cell_voltage_V", r.cell_voltage_V, cells);
  put("truth/cell_current_A", r.cell_current_A, cells);
  put("truth/cell_soc", r.cell_soc, cells);
  put("truth/cell_temp_C", r.cell_temp_C, cells);
  put("truth/pack_voltage_V", r.pack_voltage_V, 0);
  put("truth/pack_current_A", r.pack_current_A, 0);
  put("measured/cell_voltage_mV", r.meas_cell_voltage_mV, groups);
  put("measured/temperature_dC", r.meas_temperature_dC, therm);
  put("measured/current_mA", r.meas_current_mA, 0);
  put("bms/state", r.bms_state, 0);
  put("bms/fault_active", r.fault_active, 0);
  put("bms/fault_latched", r.fault_latched, 0);
  put("bms/relay_closed", r.relay_closed, 0);
  put("bms/discharge_fet_on", r.discharge_fet_on, 0);
  put("bms/charge_fet_on", r.charge_fet_on, 0);
  put("truth/soc_mean", r.soc_truth_mean, 0);
  put("truth/soc_display_bars", r.soc_display_bars_truth, 0);
  put("bms/soc_coulomb", r.soc_coulomb, 0);
  put("bms/soc_ekf", r.soc_ekf, 0);
  put("bms/soc_ekf_group_permille", r.soc_ekf_group_permille, groups);
  put("bms/capacity_estimate_Ah", r.capacity_estimate_Ah, 0);
  put("bms/soc_display_bars", r.soc_display_bars, 0);
  return d;
}

}  // namespace packsim::python
