#include "core/cli/tool_commands.hpp"

namespace packsim {

void addToolCommands(CLI::App& app, ToolCommands& t) {
  t.list = app.add_subcommand("list", "the bundled scenarios and cell presets with one-line descriptions");

  t.exportCmd = app.add_subcommand("export", "convert a result file to CSV, MATLAB .mat or Parquet "
                                             "(needs Python 3 with pandas, scipy or pyarrow)");
  t.exportCmd->add_option("result", t.exportOpts.result, "result HDF5 file")->required();
  t.exportCmd->add_option("--format", t.exportOpts.format, "csv, mat or parquet")
      ->required()
      ->check(CLI::IsMember({"csv", "mat", "parquet"}));
  t.exportCmd->add_option("-o,--output", t.exportOpts.output,
                          "output file (mat, parquet) or folder (csv); default: next to the result");

  t.reportCmd = app.add_subcommand("report", "one self-contained HTML page of a run (summary, events, figures) or "
                                             "of a batch folder (needs Python 3 with matplotlib)");
  t.reportCmd->add_option("source", t.reportOpts.source, "result HDF5 file or batch output folder")->required();
  t.reportCmd->add_option("-o,--output", t.reportOpts.output, "HTML file to write")->required();
}

std::optional<int> runToolCommand(const ToolCommands& t) {
  if (t.list->parsed()) return cmdList();
  if (t.exportCmd->parsed()) return cmdExport(t.exportOpts);
  if (t.reportCmd->parsed()) return cmdReport(t.reportOpts);
  return std::nullopt;
}

}  // namespace packsim
