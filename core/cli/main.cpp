// packsim command line: `packsim run [SCENARIO.yaml] [-o OUT.h5] [--seed N]`,
// `packsim check [PATHS...]`, `packsim plot RESULT.h5 [-o DIR]`, `packsim batch SWEEP.yaml`,
// `packsim balance-time [SCENARIO|--preset NAME] --resistor 22,33,47 [--delta-Ah A --cell-V V]`,
// `packsim fit DATA.csv... -o CELL.yaml [options]`.
#include <CLI/CLI.hpp>

#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <stdexcept>

#include "core/cli/cli_errors.hpp"
#include "core/cli/commands.hpp"
#include "core/cli/tool_commands.hpp"
#include "core/scenario/scenario_error.hpp"
#include "core/sim/stop_signal.hpp"
#include "core/version.hpp"

int main(int argc, char** argv) {
  CLI::App app{"packsim: battery-pack and BMS co-simulator", "packsim"};
  app.set_version_flag("--version", packsim::kVersion);
  app.require_subcommand(1);

  packsim::RunOptions run;
  CLI::App* runCmd = app.add_subcommand("run", "run one scenario (the bundled default if none is given)");
  runCmd->add_option("scenario", run.scenario, "scenario YAML file or bundled scenario name (packsim list; "
                                              "default: eco_marathon_12s)");
  runCmd->add_option("--set", run.set, "override a scenario value, e.g. --set pack.cell.capacity_Ah=4.5 (repeatable)");
  runCmd->add_option("-o,--output", run.output, "result HDF5 file (default: packsim-results/<name>.h5)");
  runCmd->add_option("--seed", run.seed, "override the scenario's random seed")->check(packsim::seedNumber());
  runCmd->add_flag("-q,--quiet", run.quiet, "print nothing but errors");
  runCmd->add_option("--target", run.target, "run packsim's core as ARM code on a virtual MCU (target mode)")
      ->check(CLI::IsMember({"cortex-m4"}));

  packsim::ShowOptions show;
  CLI::App* showCmd = app.add_subcommand("show", "print a scenario's values, where each came from, and its warnings");
  showCmd->add_option("scenario", show.scenario, "scenario YAML file or bundled scenario name (default: eco_marathon_12s)");
  showCmd->add_option("--set", show.set, "override a scenario value, as for run (repeatable)");
  showCmd->add_option("--format", show.format, "text (default), yaml (runnable: packsim run accepts it) or json")
      ->check(CLI::IsMember({"text", "yaml", "json"}));

  packsim::CheckOptions check;
  CLI::App* checkCmd = app.add_subcommand("check", "run scenarios and judge their expect: blocks (exit 1 on any failure)");
  checkCmd->add_option("paths", check.paths, "scenario files or folders (default: the bundled scenarios)");
  checkCmd->add_option("--target", check.target, "run each scenario's packsim core as ARM code on a virtual MCU "
                                                 "(target mode; scenarios with a host-mode firmware library are skipped)")
      ->check(CLI::IsMember({"cortex-m4"}));

  packsim::PlotOptions plot;
  CLI::App* plotCmd = app.add_subcommand("plot", "write the figures of a result file as PNG (needs Python 3 with matplotlib)");
  plotCmd->add_option("result", plot.result, "result HDF5 file")->required();
  plotCmd->add_option("-o,--output", plot.outdir, "folder for the PNG files (default: the current folder)");
  plotCmd->add_option("--dpi", plot.dpi, "resolution of the PNG files")->check(packsim::positiveNumber());

  packsim::BatchCliOptions batch;
  CLI::App* batchCmd = app.add_subcommand("batch", "run a sweep of scenarios on every core (exit 1 if any case failed)");
  batchCmd->add_option("sweep", batch.sweep, "sweep YAML file (docs/batch.md)")->required();
  batchCmd->add_option("-o,--output-dir", batch.output_dir, "folder for the results (default: the sweep's output_dir)");
  batchCmd->add_option("-j,--threads", batch.threads, "worker threads (default: every core)")->check(packsim::positiveNumber());
  batchCmd->add_flag("--no-resume", batch.no_resume, "rerun cases whose result file is already complete");
  batchCmd->add_flag("-q,--quiet", batch.quiet, "print nothing but errors");

  packsim::BalanceTimeCliOptions bal;
  CLI::App* balCmd = app.add_subcommand("balance-time", "time to balance per resistor: analytic and full simulation");
  balCmd->add_option("scenario", bal.scenario, "scenario YAML file (default: --preset bench_6s_balancing)");
  balCmd->add_option("--preset", bal.preset, "a bundled scenario by name (scenarios/ or scenarios/balance/)");
  balCmd->add_option("--resistor", bal.resistors_ohm, "balancing resistor(s) in ohm, e.g. 22,33,47,68,100 "
                                                      "(default: the scenario's)")->delimiter(',');
  balCmd->add_option("--delta-Ah", bal.delta_Ah, "imbalance to remove (default: the scenario's initial spread)");
  balCmd->add_option("--cell-V", bal.cell_V, "cell voltage of the high cells (default: OCV at the initial SOC)");
  balCmd->add_option("--high-cells", bal.high_cells, "series cells that start high with --delta-Ah (default 1)");
  balCmd->add_option("--target-mV", bal.target_mV, "true criterion: rest voltages max - min below this (default: 1.5 x the firmware's stop_delta_mV)");
  balCmd->add_option("--max-hours", bal.max_hours, "simulation cap in hours (default 72)");
  balCmd->add_flag("--analytic-only", bal.analytic_only, "skip the simulation");
  balCmd->add_option("--when", bal.when, "replace the firmware's bms.balancing.when: charging|rest|charging_or_rest|always");
  balCmd->add_flag("--during-charge", bal.during_charge, "balance on the scenario's CC-CV charger (top balancing)");
  balCmd->add_option("--plot", bal.plot, "also write a PNG: time to balance and peak board temperature vs R");

  packsim::FitCliOptions fit;
  CLI::App* fitCmd = app.add_subcommand("fit", "fit a cell preset to test CSVs (Python with SciPy; `packsim fit --help`)");
  fitCmd->prefix_command();  // every argument, --help too, goes to the Python fitter
  fitCmd->set_help_flag();

  packsim::ToolCommands tools;
  packsim::addToolCommands(app, tools);

  const std::string badCommand = packsim::unknownSubcommandError(app, argc, argv);
  if (!badCommand.empty()) {
    std::cerr << "packsim: error: " << badCommand << "\n";
    return packsim::kExitBadInput;
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return packsim::reportParseError(app, e);
  }
  packsim::installStopSignals();
  try {
    if (runCmd->parsed()) return packsim::cmdRun(run);
    if (checkCmd->parsed()) return packsim::cmdCheck(check);
    if (showCmd->parsed()) return packsim::cmdShow(show);
    if (plotCmd->parsed()) return packsim::cmdPlot(plot);
    if (batchCmd->parsed()) return packsim::cmdBatch(batch);
    if (balCmd->parsed()) return packsim::cmdBalanceTime(bal);
    if (fitCmd->parsed()) {
      fit.args = fitCmd->remaining();
      return packsim::cmdFit(fit);
    }
    if (const auto rc = packsim::runToolCommand(tools)) return *rc;
  } catch (const packsim::Interrupted& e) {
    std::cerr << "packsim: " << e.what() << "\n";
    return e.exitStatus();
  } catch (const packsim::ScenarioError& e) {
    std::cerr << "packsim: error: " << e.what() << "\n";
    return 2;
  } catch (const std::invalid_argument& e) {  // a bad option value
    std::cerr << "packsim: error: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "packsim: error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
