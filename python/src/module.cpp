// packsim._packsim: the thin pybind11 layer over the C++ core.
//
//   run(...)          load a scenario (file or text) with overrides, simulate with the
//                     GIL released, return a RunHandle that owns the C++ result
//   RunHandle         arrays() -> {hdf5 path: numpy view into the result, no copy},
//                     save(path) -> the CLI's HDF5 writer; image() -> the same file
//                     built in memory, as bytes
//   apply_overrides   core/scenario/overrides.hpp, for Python users and tests
//   show(...)         `packsim show`: {values: {key: {value, origin, stated}}, warnings, text, yaml}
//   check_*           `packsim check` (check_bindings.cpp)
//   Sweep, run_batch, run_sweep_case ...   `packsim batch` (batch_bindings.cpp)
//   balance_time, preset_path                `packsim balance-time` (balance_bindings.cpp)
//   rc_response, rc_sensitivity, simulate_cell   `packsim fit`'s simulation (fit_bindings.cpp)
//
// Everything else (the Result class, loading HDF5, plotting) is plain Python in
// python/packsim/. C++ ScenarioError becomes packsim.ScenarioError (a ValueError with
// file, line, column, field, message); std::invalid_argument a ValueError; any other
// C++ error a RuntimeError with the same message.
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <memory>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "core/cli/commands.hpp"
#include "core/io/hdf5_writer.hpp"
#include "core/scenario/scenario_inputs.hpp"
#include "core/scenario/overrides.hpp"
#include "core/scenario/provenance.hpp"
#include "core/scenario/scenario_show.hpp"
#include "core/scenario/scenario_error.hpp"
#include "core/scenario/scenario_paths.hpp"
#include "core/sim/firmware_failure.hpp"
#include "core/sim/run_progress.hpp"
#include "core/sim/simulation.hpp"
#include "core/version.hpp"
#include "python/src/bindings.hpp"
#include "python/src/result_arrays.hpp"

namespace py = pybind11;

namespace packsim::python {

namespace {

// The HDF5 library Debian ships is not built thread-safe: one writer at a time.
std::mutex& hdf5Mutex() {
  static std::mutex m;
  return m;
}

std::shared_ptr<RunHandle> run(const std::string& source, bool is_file, const Overrides& overrides,
                               std::optional<uint64_t> seed, const std::string& file_name, const std::string& base_dir,
                               const py::object& progress) {
  auto h = std::make_shared<RunHandle>();
  {
    py::gil_scoped_release release;  // loading and simulating touch no Python object
    h->scenario = loadScenarioSource(source, is_file, overrides, file_name, base_dir);
    if (seed) h->scenario.run.seed = *seed;  // exactly as `packsim run --seed N`
    StopCondition report;
    double reported_s = -1.0;
    if (!progress.is_none())  // progress(t_s, end_s) every 1 % of the run, with the GIL held just for it
      report = progressCondition(h->scenario.endTime_s(), [&progress, &reported_s](double t_s, double end_s) {
        reported_s = t_s;
        py::gil_scoped_acquire gil;
        progress(t_s, end_s);
      });
    h->result = runScenario(h->scenario, report);
    // The run's last tick, once: the loop does not ask its condition there, so a 60 s run's
    // last report was 59.4 s and a callback's bar stopped at 99 % of a finished run.
    if (!progress.is_none() && h->result.summary.duration_s > reported_s) {
      py::gil_scoped_acquire gil;
      progress(h->result.summary.duration_s, h->scenario.endTime_s());
    }
  }
  return h;
}

// `packsim show` as Python data.
py::dict show(const std::string& source, bool is_file, const Overrides& overrides, const std::string& file_name,
              const std::string& base_dir) {
  Scenario s;
  {
    py::gil_scoped_release release;
    s = loadScenarioSource(source, is_file, overrides, file_name, base_dir);
  }
  py::dict values;
  if (s.provenance)
    for (const ProvenanceEntry& e : s.provenance->entries()) {
      py::dict v;
      v["value"] = e.value;
      v["origin"] = e.origin;
      v["stated"] = e.stated;
      values[py::str(e.key)] = v;
    }
  py::dict out;
  out["values"] = values;
  out["warnings"] = py::list(py::cast(s.warnings));
  out["text"] = showText(s);
  out["yaml"] = showYaml(s);
  return out;
}

py::bytes image(const RunHandle& h) {
  std::string bytes;
  {
    py::gil_scoped_release release;
    std::lock_guard<std::mutex> lock(hdf5Mutex());
    bytes = resultHdf5Image(h.scenario, h.result);
  }
  return py::bytes(bytes);
}

void save(const RunHandle& h, const std::string& path) {
  checkResultIsNotAnInput(path, h.scenario);  // ValueError: the scenario, its extends: chain or CSV
  py::gil_scoped_release release;
  std::lock_guard<std::mutex> lock(hdf5Mutex());
  writeResultHdf5(path, h.scenario, h.result);
}

// C++ exceptions -> Python. Registered last, so tried first; what it does not handle
// (pybind11's own exceptions) it passes on by rethrowing.
void translate(std::exception_ptr p) {
  try {
    std::rethrow_exception(p);
  } catch (const ScenarioError& e) {
    py::object cls;
    try {
      cls = py::module_::import("packsim._errors").attr("ScenarioError");
    } catch (py::error_already_set&) {
      PyErr_SetString(PyExc_ValueError, e.what());  // extension imported without its package
      return;
    }
    py::object exc = cls(e.what(), py::arg("file") = e.file(), py::arg("line") = e.line(),
                         py::arg("column") = e.column(), py::arg("field") = e.field(), py::arg("message") = e.message());
    PyErr_SetObject(cls.ptr(), exc.ptr());
  } catch (const py::builtin_exception&) {
    throw;
  } catch (const py::error_already_set&) {
    throw;
  } catch (const std::invalid_argument& e) {  // a bad option (balance_time, preset names)
    PyErr_SetString(PyExc_ValueError, e.what());
  } catch (const std::exception& e) {
    PyErr_SetString(PyExc_RuntimeError, e.what());
  }
}

}  // namespace

Scenario loadScenarioSource(const std::string& source, bool is_file, const Overrides& overrides,
                            const std::string& file_name, const std::string& base_dir) {
  return is_file ? loadScenarioFileWithOverrides(source, overrides)
                 : loadScenarioWithOverrides(source, overrides, file_name, base_dir);
}

}  // namespace packsim::python

PYBIND11_MODULE(_packsim, m) {
  using namespace packsim;
  using namespace packsim::python;
  m.doc() = "packsim C++ core: run scenarios, write results (use the `packsim` package, not this module)";
  m.attr("__version__") = kVersion;

  py::class_<RunHandle, std::shared_ptr<RunHandle>>(m, "RunHandle",
                                                    "Owns one run's C++ scenario and result; arrays view into it.")
      .def("arrays", &recordingArrays,
           "{HDF5 dataset path: read-only numpy view of the C++ recording} (no copy; the arrays keep "
           "this handle alive)")
      .def("save", &save, py::arg("path"), "write the result HDF5 exactly as `packsim run -o PATH` does")
      .def("image", &image, "the result HDF5 file built in memory (uncompressed), as bytes; nothing is written")
      .def_property_readonly("scenario_yaml", [](const RunHandle& h) { return h.scenario.text; })
      .def_property_readonly("scenario_name", [](const RunHandle& h) { return h.scenario.name; })
      .def_property_readonly("seed", [](const RunHandle& h) { return h.scenario.run.seed; })
      .def_property_readonly(
          "firmware_failure",
          [](const RunHandle& h) {
            return h.scenario.expect.firmware_fault ? std::string() : firmwareFailure(h.scenario, h.result);
          },
          "why the run's firmware failed (not loaded, contract broken, crashed, hung), unless the scenario "
          "expects it; '' otherwise");

  m.def("result_channels", &resultChannelTable,
        "the result-channel table: [{path, units, axis, dtype, long_name}] in file order");
  m.def("run", &run, py::arg("source"), py::arg("is_file"), py::arg("overrides"), py::arg("seed") = py::none(),
        py::arg("file_name") = "<scenario>", py::arg("base_dir") = ".", py::arg("progress") = py::none(),
        "Load a scenario (a file path if is_file, else YAML text named file_name whose relative paths resolve "
        "against base_dir), apply the (dotted key, YAML value) overrides, run it with the GIL released; "
        "progress(t_s, end_s), if given, is called every 1 % of simulated time.");
  m.def("show", &show, py::arg("source"), py::arg("is_file"), py::arg("overrides"), py::arg("file_name") = "<scenario>",
        py::arg("base_dir") = ".",
        "Load a scenario as run() does and return {values: {key: {value, origin, stated}}, warnings: [...], "
        "text: the `packsim show` text, yaml: the runnable `packsim show --format yaml` text}.");
  m.def("apply_overrides", &applyOverrides, py::arg("yaml_text"), py::arg("overrides"),
        py::arg("file_name") = "<scenario>", "The scenario text with (dotted key, YAML value) overrides applied.");
  m.def("bundled_scenario_dir", &bundledScenarioDir, "Folder of the bundled scenarios ($PACKSIM_SCENARIOS overrides).");
  m.def("default_scenario_path", &defaultScenarioPath, "The scenario `packsim run` uses without arguments.");
  m.def("bundled_catalog", []() {
    std::vector<std::tuple<std::string, std::string, std::string, std::string>> out;
    for (const CatalogEntry& e : bundledCatalog()) out.emplace_back(e.kind, e.name, e.path, e.description);
    return out;
  }, "[(kind, name, path, description)] of the bundled scenarios and cell presets, as `packsim list` prints them.");
  m.def("scenario_arg_path", &scenarioArgPath, py::arg("arg"),
        "A scenario argument as a path: an existing file, else a bundled scenario by name (ValueError if none).");
  bindCheck(m);
  bindBatch(m);
  bindBalance(m);
  bindFit(m);

  py::register_exception_translator(&translate);
}
