#include "python/src/result_arrays.hpp"

#include <pybind11/numpy.h>

#include <stdexcept>
#include <string>
#include <variant>
#include <vector>

#include "core/sim/result_channels.hpp"

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
  py::dict d;
  for (const ResultChannel& c : resultChannels()) {  // core/sim/result_channels.hpp
    if (!isRecorded(c, r)) continue;
    const char* key = c.path + 1;  // without the leading '/'
    std::visit([&](const auto& col) { d[key] = view(r.*(col.data), r.samples(), axisLength(c.axis, r), handle, key); },
               c.column);
  }
  return d;
}

py::list resultChannelTable() {
  py::list out;
  for (const ResultChannel& c : resultChannels()) {
    py::dict row;
    row["path"] = c.path;
    row["units"] = c.units ? py::object(py::str(c.units)) : py::object(py::none());
    row["axis"] = axisName(c.axis);
    row["dtype"] = dtypeName(c);
    row["long_name"] = c.long_name;
    out.append(row);
  }
  return out;
}

}  // namespace packsim::python
