#include "core/cli/cli_errors.hpp"

#include <charconv>
#include <cstdint>

#include <cmath>
#include <iostream>
#include <vector>

#include "core/scenario/scenario_error.hpp"  // closestMatch
#include "core/scenario/value_ranges.hpp"

namespace packsim {

namespace {

std::vector<std::string> subcommandNames(const CLI::App& app) {
  std::vector<std::string> names;
  for (const CLI::App* s : app.get_subcommands([](const CLI::App*) { return true; })) names.push_back(s->get_name());
  return names;
}

std::string joined(const std::vector<std::string>& v) {
  std::string out;
  for (const auto& s : v) out += (out.empty() ? "" : ", ") + s;
  return out;
}

// The options a (sub)command accepts, as typed: --long and -s.
std::vector<std::string> optionSpellings(const CLI::App& app) {
  std::vector<std::string> names;
  for (const CLI::Option* o : app.get_options()) {
    for (const std::string& l : o->get_lnames()) names.push_back("--" + l);
    for (const std::string& s : o->get_snames()) names.push_back("-" + s);
  }
  return names;
}

// The deepest subcommand that was named on the command line (or the app).
CLI::App* activeCommand(CLI::App& app) {
  for (CLI::App* s : app.get_subcommands()) return activeCommand(*s);
  return &app;
}

std::string commandName(const CLI::App& app, const CLI::App& cmd) {
  return &cmd == &app ? "packsim" : "packsim " + cmd.get_name();
}

std::string parseNumber(const std::string& text, double& v) {
  try {
    size_t used = 0;
    v = std::stod(text, &used);
    if (used != text.size() || !std::isfinite(v)) return "expected a number, got '" + text + "'";
  } catch (const std::exception&) {
    return "expected a number, got '" + text + "'";
  }
  return "";
}

// A number that `ok` accepts; `bound` ("> 0") names the rule in the error and the help.
CLI::Validator boundedNumber(bool (*ok)(double), const std::string& bound) {
  return CLI::Validator(
      [ok, bound](std::string& text) {
        double v = 0.0;
        const std::string bad = parseNumber(text, v);
        if (!bad.empty()) return bad;
        return ok(v) ? std::string() : "must be " + bound + ", got " + text;
      },
      "NUMBER " + bound);
}

}  // namespace

std::string unknownSubcommandError(const CLI::App& app, int argc, const char* const* argv) {
  if (argc < 2 || argv[1][0] == '-') return "";
  const std::string given = argv[1];
  const std::vector<std::string> names = subcommandNames(app);
  for (const auto& n : names)
    if (n == given) return "";
  const std::string near = closestMatch(given, names);
  return "unknown command '" + given + "'" + (near.empty() ? "" : "; did you mean '" + near + "'?") +
         " (commands: " + joined(names) + ")";
}

int reportParseError(CLI::App& app, const CLI::ParseError& e) {
  if (dynamic_cast<const CLI::Success*>(&e) || dynamic_cast<const CLI::CallForHelp*>(&e) ||
      dynamic_cast<const CLI::CallForAllHelp*>(&e) || dynamic_cast<const CLI::CallForVersion*>(&e))
    return app.exit(e);
  CLI::App* cmd = activeCommand(app);
  std::string message = e.what();
  if (dynamic_cast<const CLI::ExtrasError*>(&e)) {
    std::vector<std::string> extras = cmd->remaining();
    if (extras.empty()) extras = app.remaining();
    const std::string first = extras.empty() ? std::string() : extras.front();
    if (!first.empty() && first[0] == '-') {
      const std::string option = first.substr(0, first.find('='));
      const std::string near = closestMatch(option, optionSpellings(*cmd));
      message = "unknown option '" + option + "'" + (near.empty() ? "" : "; did you mean '" + near + "'?");
    } else if (!first.empty()) {
      message = "unexpected argument '" + first + "'";
    }
  } else if (dynamic_cast<const CLI::RequiredError*>(&e) && cmd == &app) {
    message = "a command is required (commands: " + joined(subcommandNames(app)) + ")";
  }
  std::cerr << commandName(app, *cmd) << ": error: " << message << " (see " << commandName(app, *cmd)
            << " --help)\n";
  return kExitBadInput;
}

CLI::Validator nonNegativeNumber() { return boundedNumber([](double v) { return v >= 0.0; }, ">= 0"); }

CLI::Validator positiveNumber() { return boundedNumber([](double v) { return v > 0.0; }, "> 0"); }

CLI::Validator seedNumber() {
  const std::string range = "[0, " + std::to_string(limits::kMaxSeed) + "]";
  return CLI::Validator(
      [range](std::string& text) {
        uint64_t v = 0;
        const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
        if (ec != std::errc() || end != text.data() + text.size() || v > static_cast<uint64_t>(limits::kMaxSeed))
          return "expected a whole number in " + range + " (a scenario's seed: range), got " + text;
        return std::string();
      },
      "INT in " + range);
}

}  // namespace packsim
