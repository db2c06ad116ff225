// Command-line argument errors: one short line on stderr, exit status 2, and the
// closest valid subcommand or option when a name is mistyped.
#pragma once
#include <CLI/CLI.hpp>

#include <string>

namespace packsim {

// Exit status of every argument error (README: 0 success, 2 bad input, 1 a failed run).
constexpr int kExitBadInput = 2;

// A mistyped subcommand (argv[1] not an option and not a subcommand's name): the one-line
// error, or "" when argv[1] is fine.
std::string unknownSubcommandError(const CLI::App& app, int argc, const char* const* argv);
// Prints a CLI11 parse error as one line (with "did you mean" for an unknown option) and
// returns the exit status: 0 for --help/--version, kExitBadInput otherwise.
int reportParseError(CLI::App& app, const CLI::ParseError& e);
// Validators whose message states the allowed range in words (CLI11's own print the
// whole double range).
CLI::Validator nonNegativeNumber();
CLI::Validator positiveNumber();
// The --seed options: a whole number in a scenario's `seed:` range [0, limits::kMaxSeed]
// (a batch's Monte Carlo seeds are drawn in it too), so a value is never wrapped or cut.
CLI::Validator seedNumber();

}  // namespace packsim
