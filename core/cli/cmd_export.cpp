// `packsim export RESULT.h5 --format csv|mat|parquet [-o OUT]` and
// `packsim report RESULT.h5|BATCH_DIR -o report.html`: both live in the Python package
// (python/packsim/export.py, report.py), where the libraries that write these formats
// are; this runs `python3 -m packsim export|report` (core/cli/python_module.hpp): the
// package's __main__, not `-m packsim.report`, which runpy warns about because
// `import packsim` has already imported packsim.report.
#include <filesystem>

#include "core/cli/commands.hpp"
#include "core/cli/python_module.hpp"
#include "core/scenario/scenario_error.hpp"

namespace packsim {

int cmdExport(const ExportOptions& o) {
  if (!std::filesystem::is_regular_file(o.result)) throw ScenarioError(o.result, 0, 0, "", "no such result file");
  std::vector<std::string> args = {o.result, "--format", o.format};
  if (!o.output.empty()) {
    args.push_back("-o");
    args.push_back(o.output);
  }
  args.insert(args.begin(), "export");
  return runPythonModule("packsim", args,
                         "numpy, h5py and pandas (csv), scipy (mat) or pyarrow (parquet)");
}

int cmdReport(const ReportOptions& o) {
  if (!std::filesystem::exists(o.source))
    throw ScenarioError(o.source, 0, 0, "", "no such result file or batch folder");
  return runPythonModule("packsim", {"report", o.source, "-o", o.output}, "numpy, h5py and plotly");
}

}  // namespace packsim
