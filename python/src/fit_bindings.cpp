// `packsim fit`'s simulation in C++ (core/fit/ecm_zoh.hpp): the RC responses and their
// derivatives the fitter's Jacobian is built from, and the model voltage of a preset over
// a record, as numpy arrays.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <stdexcept>
#include <string>
#include <vector>

#include "core/fit/ecm_zoh.hpp"
#include "python/src/bindings.hpp"

namespace py = pybind11;

namespace packsim::python {

namespace {

using Array = py::array_t<double, py::array::c_style | py::array::forcecast>;

size_t length(const Array& a, const char* name, size_t n) {
  if (a.ndim() != 1) throw std::invalid_argument(std::string(name) + ": expected a 1-D array");
  if (n != 0 && static_cast<size_t>(a.shape(0)) != n)
    throw std::invalid_argument(std::string(name) + ": " + std::to_string(a.shape(0)) + " values, expected " +
                                std::to_string(n));
  return static_cast<size_t>(a.shape(0));
}

size_t tauLength(const Array& tau, size_t n) {
  const size_t len = length(tau, "tau_s", 0);
  if (len != 1 && len != n) throw std::invalid_argument("tau_s: one value or one per sample");
  for (ssize_t k = 0; k < tau.shape(0); ++k)
    if (!(tau.data()[k] > 0.0)) throw std::invalid_argument("tau_s: values must be > 0");
  return len;
}

Array rcResponse(const Array& time_s, const Array& x, const Array& tau_s) {
  const size_t n = length(time_s, "time_s", 0);
  length(x, "x", n);
  const size_t tl = tauLength(tau_s, n);
  Array v(std::vector<ssize_t>{static_cast<ssize_t>(n)});
  withoutGil([&] {
    fit::rcResponse(time_s.data(), x.data(), n, tau_s.data(), tl, v.mutable_data());
    return 0;
  });
  return v;
}

py::tuple rcSensitivity(const Array& time_s, const Array& x, const Array& tau_s, const Array& dlogtau) {
  const size_t n = length(time_s, "time_s", 0);
  length(x, "x", n);
  const size_t tl = tauLength(tau_s, n);
  if (dlogtau.ndim() != 2 || static_cast<size_t>(dlogtau.shape(0)) != n)
    throw std::invalid_argument("dlogtau: expected an array of shape (samples, parameters)");
  const size_t m = static_cast<size_t>(dlogtau.shape(1));
  Array v(std::vector<ssize_t>{static_cast<ssize_t>(n)});
  Array s({static_cast<ssize_t>(n), static_cast<ssize_t>(m)});
  withoutGil([&] {
    fit::rcSensitivity(time_s.data(), x.data(), n, tau_s.data(), tl, dlogtau.data(), m, v.mutable_data(),
                       s.mutable_data());
    return 0;
  });
  return py::make_tuple(v, s);
}

std::vector<double> vec(const Array& a, const char* name, size_t n) {
  length(a, name, n);
  return std::vector<double>(a.data(), a.data() + a.shape(0));
}

Array simulateCell(const std::string& preset_yaml, const Array& time_s, const Array& current_A, const Array& held_A,
                   const Array& temp_C, double initial_soc, const std::string& file) {
  const size_t n = length(time_s, "time_s", 0);
  std::vector<double> t = vec(time_s, "time_s", n), i = vec(current_A, "current_A", n), u = vec(held_A, "held_A", n),
                      temp = vec(temp_C, "temp_C", n);
  std::vector<double> out = withoutGil([&] {
    const CellParams cell = fit::cellFromYaml(preset_yaml, file);
    return fit::simulateCell(cell, t, i, u, temp, initial_soc);
  });
  Array a(std::vector<ssize_t>{static_cast<ssize_t>(n)});
  std::copy(out.begin(), out.end(), a.mutable_data());
  return a;
}

}  // namespace

void bindFit(py::module_& m) {
  m.def("rc_response", &rcResponse, py::arg("time_s"), py::arg("x"), py::arg("tau_s"),
        "v[0] = 0, v[k+1] = a·v[k] + (1 - a)·x[k], a = exp(-dt_k/tau_k): one RC branch under a zero-order hold "
        "(tau_s: one value or one per sample)");
  m.def("rc_sensitivity", &rcSensitivity, py::arg("time_s"), py::arg("x"), py::arg("tau_s"), py::arg("dlogtau"),
        "(v, dv/dtheta): rc_response and its derivatives for parameters theta_j of log tau, "
        "dlogtau[k, j] = d log tau_k / d theta_j");
  m.def("simulate_cell", &simulateCell, py::arg("preset_yaml"), py::arg("time_s"), py::arg("current_A"),
        py::arg("held_A"), py::arg("temp_C"), py::arg("initial_soc"), py::arg("file") = "<preset>",
        "Terminal voltage of a cell preset (YAML text) over a record: current_A at each sample, held_A held over "
        "the interval after it, temp_C per sample; the cell starts at rest at initial_soc");
}

}  // namespace packsim::python
