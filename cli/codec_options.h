#pragma once
// The table codec's options of the commands that write box files: --codec NAME[,bound...] and,
// for compress, --max-error, --ratio, --normal-bits and --strict.
#include "codec/codec.h"
#include <CLI/CLI.hpp>
#include <string>
#include <vector>

namespace hb::cli {

/// Adds --max-error, --ratio (mutually exclusive) and --normal-bits to a command; returns the
/// --max-error option (to tell whether it was given).
/// `strict` (optional): adds --strict, failing the command when --ratio's target is not met.
CLI::Option* add_codec_bound_options(CLI::App& cmd, CodecOptions& options, bool* strict = nullptr);

/// --codec NAME[,max-error=E|ratio=R][,normal-bits=B][,strict]: the table codec and its bound,
/// into `codec` (name) and `options` (bound); `strict` (optional) allows the strict key,
/// failing the command when the ratio's target is not met. `given` (optional) is set when a
/// bound (max-error or ratio) was given. `allowed`: the codec names.
CLI::Option* add_codec_option(CLI::App& cmd, std::string& codec, CodecOptions& options, bool* strict,
                              bool* bound_given, const std::vector<std::string>& allowed, const std::string& help);

} // namespace hb::cli
