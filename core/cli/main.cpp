// packsim command line: `packsim run [SCENARIO.yaml] [-o OUT.h5] [--seed N]`.
#include <CLI/CLI.hpp>

#include <cstdlib>
#include <filesystem>
#include <iostream>

#include "core/cli/commands.hpp"
#include "core/scenario/scenario_error.hpp"
#include "core/version.hpp"

int main(int argc, char** argv) {
  CLI::App app{"packsim: battery-pack and BMS co-simulator"};
  app.set_version_flag("--version", packsim::kVersion);
  app.require_subcommand(1);

  packsim::RunOptions run;
  CLI::App* runCmd = app.add_subcommand("run", "run one scenario (the bundled default if none is given)");
  runCmd->add_option("scenario", run.scenario, "scenario YAML file (default: " + packsim::defaultScenarioPath() + ")");
  runCmd->add_option("-o,--output", run.output, "result HDF5 file (default: packsim-results/<name>.h5)");
  runCmd->add_option("--seed", run.seed, "override the scenario's random seed")->check(CLI::NonNegativeNumber);
  runCmd->add_flag("-q,--quiet", run.quiet, "print nothing but errors");

  packsim::CheckOptions check;
  CLI::App* checkCmd = app.add_subcommand("check", "run scenarios and judge their expect: blocks (exit 1 on any failure)");
  checkCmd->add_option("paths", check.paths, "scenario files or folders (default: the bundled scenarios)");

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  try {
    if (runCmd->parsed()) return packsim::cmdRun(run);
    if (checkCmd->parsed()) return packsim::cmdCheck(check);
  } catch (const packsim::ScenarioError& e) {
    std::cerr << "packsim: error: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "packsim: error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
