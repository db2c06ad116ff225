// `packsim export RESULT.h5 --format csv|mat|parquet [-o OUT]` and
// `packsim report RESULT.h5|BATCH_DIR -o report.html`: both live in the Python package
// (python/packsim/export.py, report.py), where the libraries that write these formats
// are; this runs `python3 -m packsim export|report` (core/cli/python_module.hpp): the
// package's __main__, not `-m packsim.report`, which runpy warns about because
// `import packsim` has already imported packsim.report.
#include <filesystem>
#include <stdexcept>

#include "core/cli/commands.hpp"
#include "core/cli/python_module.hpp"
#include "core/scenario/scenario_error.hpp"

namespace packsim {

namespace {

// --format, or the output file's extension when it names one format: `-o run.mat`,
// `-o run.parquet`. A CSV export writes a folder (one table a file), so `-o run.csv`
// names no format: the error says what to give.
std::string exportFormat(const ExportOptions& o) {
  if (!o.format.empty()) return o.format;
  const std::filesystem::path out(o.output);
  const std::string ext = out.extension().string();
  if (ext == ".mat") return "mat";
  if (ext == ".parquet") return "parquet";
  if (ext == ".csv")
    throw std::invalid_argument("--format missing; a CSV export writes a folder, one CSV file per table: give "
                                "--format csv with -o a folder (e.g. -o " + out.stem().string() + "_csv)");
  throw std::invalid_argument("--format missing: csv, mat or parquet (or -o FILE.mat or FILE.parquet)");
}

}  // namespace

int cmdExport(const ExportOptions& o) {
  if (!std::filesystem::is_regular_file(o.result)) throw ScenarioError(o.result, 0, 0, "", "no such result file");
  std::vector<std::string> args = {o.result, "--format", exportFormat(o)};
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
