// Sweeps and batch runs for Python (core/batch/): the C++ expansion of a sweep into
// cases, the CLI's thread pool, and the single-case runner a Dask task calls.
//
//   load_sweep / load_sweep_text   the sweep YAML -> Sweep (strict; ScenarioError)
//   run_batch(sweep, ...)          `packsim batch`: every case on a C++ thread pool
//   run_sweep_case(sweep, i, ...)  one case exactly as the pool runs it (never throws)
//   write_summary_csv(sweep, ...)  summary.csv from outcomes gathered elsewhere
//
// Sweep pickles (Dask ships it to workers); outcomes are plain dicts. The GIL is
// released while anything runs.
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "core/batch/batch_runner.hpp"
#include "core/batch/sweep.hpp"
#include "core/scenario/overrides.hpp"
#include "python/src/bindings.hpp"

namespace py = pybind11;

namespace packsim::python {

namespace {

using Params = std::vector<std::pair<std::string, std::string>>;

py::dict outcomeDict(const CaseOutcome& o) {
  py::dict d;
  d["ok"] = o.ok;
  d["skipped"] = o.skipped;
  d["wall_s"] = o.wall_s;
  d["error"] = o.error;
  d["summary"] = o.summary;
  return d;
}

CaseOutcome outcomeFrom(const py::handle& h) {
  if (!py::isinstance<py::dict>(h)) throw py::type_error("each outcome must be a dict as run_sweep_case returns");
  const py::dict d = py::reinterpret_borrow<py::dict>(h);
  CaseOutcome o;
  o.ok = d["ok"].cast<bool>();
  o.skipped = d.contains("skipped") && d["skipped"].cast<bool>();
  o.wall_s = d.contains("wall_s") ? d["wall_s"].cast<double>() : 0.0;
  o.error = d.contains("error") ? d["error"].cast<std::string>() : std::string();
  o.summary = d["summary"].cast<Params>();
  return o;
}

const SweepCase& caseAt(const Sweep& s, long index) {
  if (index < 0 || index >= static_cast<long>(s.cases.size()))
    throw py::index_error("case index " + std::to_string(index) + " out of range: the sweep has " +
                          std::to_string(s.cases.size()) + " cases");
  return s.cases[static_cast<size_t>(index)];
}

std::string caseLabel(const Sweep& s, const SweepCase& c) {
  return s.base_path + " (sweep " + s.name + ", case " + c.id + ")";  // as core/batch names a case
}

std::string baseDir(const Sweep& s) {
  const std::string dir = std::filesystem::path(s.base_path).parent_path().string();
  return dir.empty() ? "." : dir;
}

// [(index, id, params), ...]: Sweep.cases and the pickle state
py::list casesList(const Sweep& s) {
  return listOf(s.cases, [](const SweepCase& c) { return py::make_tuple(c.index, c.id, c.params); });
}

py::tuple sweepState(const Sweep& s) {
  return py::make_tuple(s.name, s.file, s.base_path, s.base_text, s.output_dir, s.threads, s.keys, casesList(s));
}

Sweep sweepFromState(const py::tuple& t) {
  if (t.size() != 8) throw std::runtime_error("invalid Sweep pickle state");
  Sweep s;
  s.name = t[0].cast<std::string>();
  s.file = t[1].cast<std::string>();
  s.base_path = t[2].cast<std::string>();
  s.base_text = t[3].cast<std::string>();
  s.output_dir = t[4].cast<std::string>();
  s.threads = t[5].cast<int>();
  s.keys = t[6].cast<std::vector<std::string>>();
  for (const py::handle c : t[7].cast<py::list>()) {
    const py::tuple ct = c.cast<py::tuple>();
    s.cases.push_back(SweepCase{ct[0].cast<int>(), ct[1].cast<std::string>(), ct[2].cast<Params>()});
  }
  return s;
}

Sweep withOutputDir(Sweep s, const std::string& output_dir) {
  if (!output_dir.empty()) s.output_dir = output_dir;
  return s;
}

}  // namespace

void bindBatch(py::module_& m) {
  py::class_<Sweep>(m, "Sweep", "A base scenario and the cases of a sweep (core/batch/sweep.hpp).")
      .def_readonly("name", &Sweep::name)
      .def_readonly("file", &Sweep::file, "the sweep YAML's path ('' for text)")
      .def_readonly("base_path", &Sweep::base_path, "the base scenario file")
      .def_readonly("base_text", &Sweep::base_text, "the base scenario's YAML")
      .def_readonly("output_dir", &Sweep::output_dir, "where case_<id>.h5 and summary.csv go")
      .def_readonly("threads", &Sweep::threads, "the sweep's `threads` (0: every core)")
      .def_readonly("keys", &Sweep::keys, "the varied dotted keys, in column order")
      .def_property_readonly("cases", &casesList, "[(index, id, [(dotted key, YAML value), ...]), ...] in sweep order")
      .def(
          "result_path", [](const Sweep& s, long index) { return s.resultPath(caseAt(s, index)); }, py::arg("index"),
          "<output_dir>/case_<id>.h5 of case `index`")
      .def("summary_csv_path", &Sweep::summaryCsvPath, "<output_dir>/summary.csv")
      .def(
          "case_yaml",
          [](const Sweep& s, long index) {
            const SweepCase& c = caseAt(s, index);
            return applyOverrides(s.base_text, c.params, caseLabel(s, c));
          },
          py::arg("index"), "the scenario text of case `index` (the base with the case's parameters applied)")
      .def("__len__", [](const Sweep& s) { return s.cases.size(); })
      .def(py::pickle([](const Sweep& s) { return sweepState(s); }, [](const py::tuple& t) { return sweepFromState(t); }));

  m.def(
      "load_sweep",
      [](const std::string& path, const std::string& output_dir) {
        py::gil_scoped_release release;
        return withOutputDir(loadSweepFile(path), output_dir);
      },
      py::arg("path"), py::arg("output_dir") = "",
      "Load a sweep YAML file strictly (relative paths resolve against its folder); output_dir, if given, "
      "replaces the sweep's.");
  m.def(
      "load_sweep_text",
      [](const std::string& text, const std::string& file, const std::string& base_dir, const std::string& output_dir) {
        py::gil_scoped_release release;
        return withOutputDir(loadSweepText(text, file, base_dir), output_dir);
      },
      py::arg("text"), py::arg("file"), py::arg("base_dir"), py::arg("output_dir") = "",
      "Load sweep YAML text named `file`, its relative paths resolved against base_dir.");
  m.def("monte_carlo_seed", &monteCarloSeed, py::arg("master_seed"), py::arg("sample"),
        "The scenario seed of Monte Carlo sample i (splitmix64, masked to [0, 2^31-1]).");
  m.def(
      "validate_sweep_case",
      [](const Sweep& s, long index) {
        const SweepCase& c = caseAt(s, index);
        py::gil_scoped_release release;
        loadScenarioWithOverrides(s.base_text, c.params, caseLabel(s, c), baseDir(s));
      },
      py::arg("sweep"), py::arg("index"),
      "Load case `index` strictly without running it: a ScenarioError if it is invalid (`packsim batch` checks "
      "the first case so before anything runs).");
  m.def(
      "run_sweep_case",
      [](const Sweep& s, long index, bool resume) {
        const SweepCase& c = caseAt(s, index);
        return outcomeDict(withoutGil([&] { return runSweepCase(s, c, resume); }));
      },
      py::arg("sweep"), py::arg("index"), py::arg("resume") = true,
      "Run one case as `packsim batch` does (skipped when its result is complete and resume); never raises: "
      "an outcome dict (ok, skipped, wall_s, error, summary).");
  m.def(
      "run_batch",
      [](const Sweep& s, int threads, bool resume, bool progress) {
        BatchOptions opt;
        opt.threads = threads;
        opt.resume = resume;
        opt.progress = progress ? stdout : nullptr;
        const BatchReport r = withoutGil([&] { return runBatch(s, opt); });
        py::dict d;
        d["total"] = r.total;
        d["ok"] = r.ok;
        d["failed"] = r.failed;
        d["skipped"] = r.skipped;
        d["threads"] = r.threads;
        d["wall_s"] = r.wall_s;
        d["csv_path"] = r.csv_path;
        d["cases"] = listOf(r.cases, outcomeDict);
        return d;
      },
      py::arg("sweep"), py::arg("threads") = 0, py::arg("resume") = true, py::arg("progress") = false,
      "Run every case on a C++ thread pool exactly as `packsim batch` (GIL released); writes the results and "
      "summary.csv; a report dict.");
  m.def(
      "write_summary_csv",
      [](const Sweep& s, const py::list& outcomes) {
        if (outcomes.size() != s.cases.size())
          throw py::value_error("expected one outcome per case (" + std::to_string(s.cases.size()) + "), got " +
                                std::to_string(outcomes.size()));
        BatchReport r;
        r.csv_path = s.summaryCsvPath();
        for (const py::handle h : outcomes) r.cases.push_back(outcomeFrom(h));
        py::gil_scoped_release release;
        std::filesystem::create_directories(s.output_dir);
        writeSummaryCsv(s, r);
        return r.csv_path;
      },
      py::arg("sweep"), py::arg("outcomes"), "Write summary.csv from one outcome dict per case, in sweep order.");
}

}  // namespace packsim::python
