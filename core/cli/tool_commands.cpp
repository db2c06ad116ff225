#include "core/cli/tool_commands.hpp"

namespace packsim {

void addToolCommands(CLI::App& app, ToolCommands& t) {
  t.list = app.add_subcommand("list", "the bundled scenarios and cell presets with one-line descriptions");

  t.exportCmd = app.add_subcommand("export", "convert a result file to CSV, MATLAB .mat or Parquet "
                                             "(needs Python 3 with pandas, scipy or pyarrow)");
  t.exportCmd->add_option("result", t.exportOpts.result, "result HDF5 file")->required();
  t.exportCmd->add_option("--format", t.exportOpts.format, "csv, mat or parquet (default: from -o FILE.mat or FILE.parquet)")
      ->check(CLI::IsMember({"csv", "mat", "parquet"}));
  t.exportCmd->add_option("-o,--output", t.exportOpts.output,
                          "output file (mat, parquet) or folder (csv); default: next to the result");

  t.reportCmd = app.add_subcommand("report", "one self-contained interactive HTML page of a run (verdict, margins, "
                                             "figures, events) or of a batch folder (needs Python 3 with plotly)");
  t.reportCmd->add_option("source", t.reportOpts.source, "result HDF5 file or batch output folder")->required();
  t.reportCmd->add_option("-o,--output", t.reportOpts.output, "HTML file to write")->required();

  t.fmuCmd = app.add_subcommand("fmu", "the scenario's pack, hardware and BMS as an FMI 2.0 co-simulation FMU (docs/fmu.md)");
  t.fmuCmd->add_option("scenario", t.fmuOpts.scenario, "scenario YAML file or bundled scenario name")->required();
  t.fmuCmd->add_option("-o,--output", t.fmuOpts.output, "FMU file to write")->required();
  t.fmuCmd->add_flag("-q,--quiet", t.fmuOpts.quiet, "print nothing but errors");
}

std::optional<int> runToolCommand(const ToolCommands& t) {
  if (t.list->parsed()) return cmdList();
  if (t.exportCmd->parsed()) return cmdExport(t.exportOpts);
  if (t.reportCmd->parsed()) return cmdReport(t.reportOpts);
  if (t.fmuCmd->parsed()) return cmdFmu(t.fmuOpts);
  return std::nullopt;
}

}  // namespace packsim
