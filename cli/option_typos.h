#pragma once
// Unknown long options named with the nearest real one: `--ouput` says "did you mean
// --output?" instead of CLI11's "--output is required".
#include <CLI/CLI.hpp>
#include <string>

namespace hb::cli {

/// The message for the first `--name` (or `--name=value`) in argv that neither the command
/// `command` nor the program takes, naming the nearest option when one is close; empty when
/// every option is known (or there is no such command).
std::string unknown_option_message(const CLI::App& app, const std::string& command, int argc, char** argv);

} // namespace hb::cli
