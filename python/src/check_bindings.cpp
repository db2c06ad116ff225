// `packsim check` for Python (core/check/check.hpp): judge a scenario's expect: block and
// measure the detection latency of every injected fault. Outcomes cross as plain dicts;
// python/packsim/check.py turns them into CheckOutcome objects and the CLI's text.
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <string>
#include <vector>

#include "core/check/check.hpp"
#include "python/src/bindings.hpp"
#include "python/src/result_arrays.hpp"

namespace py = pybind11;

namespace packsim::python {

namespace {

py::object seconds(double s) { return s < 0.0 ? py::none() : py::object(py::float_(s)); }

py::dict outcomeDict(const CheckOutcome& o) {
  py::list latencies;
  for (size_t i = 0; i < o.fault_latencies.size(); ++i) {
    const FaultLatency& f = o.fault_latencies[i];
    py::dict d;
    d["injected"] = f.injected;
    d["injected_at_s"] = f.injected_at_s;
    d["detected_fault"] = f.detected_fault.empty() ? py::object(py::none()) : py::object(py::str(f.detected_fault));
    d["detection_latency_s"] = seconds(f.detection_latency_s);
    d["relay_open_latency_s"] = seconds(f.relay_open_latency_s);
    d["line"] = i < o.latencies.size() ? o.latencies[i] : std::string();
    latencies.append(d);
  }
  py::dict d;
  d["name"] = o.name;
  d["passed"] = o.passed;
  d["error"] = o.error ? py::object(py::str(o.error_message)) : py::object(py::none());
  d["failures"] = o.failures;
  d["latencies"] = latencies;
  d["warnings"] = py::cast(o.warnings);
  d["verdict"] = o.verdict;
  d["nothing_to_check"] = o.nothing_to_check;
  return d;
}

}  // namespace

void bindCheck(py::module_& m) {
  m.def(
      "check_file",
      [](const std::string& path) {
        // checkScenarioFile never throws: errors become error outcomes
        return outcomeDict(withoutGil([&] { return checkScenarioFile(path); }));
      },
      py::arg("path"),
      "Load, run and judge one scenario file exactly as `packsim check` does (GIL released); "
      "an outcome dict (name, passed, error, failures, latencies, verdict).");
  m.def(
      "check_run",
      [](const RunHandle& h) { return outcomeDict(withoutGil([&] { return judge(h.scenario, h.result); })); },
      py::arg("handle"), "Judge a finished run against its scenario's expect: block; an outcome dict.");
  m.def("collect_scenario_files", &collectScenarioFiles, py::arg("paths"),
        "Scenario files under the given files and folders, as `packsim check` finds them (folders recursively, "
        "sorted, skipping cells/ and profiles/).");
}

}  // namespace packsim::python
