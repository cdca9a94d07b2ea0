#include "codec_options.h"
#include "spec_option.h"
#include <algorithm>

namespace hb::cli {

CLI::Option* add_codec_option(CLI::App& cmd, std::string& codec, CodecOptions& options, bool* strict,
                              bool* bound_given, const std::vector<std::string>& allowed, const std::string& help) {
  return cmd.add_option_function<std::string>(
      "--codec",
      [&codec, &options, strict, bound_given, allowed](const std::string& spec) {
        std::string name = codec;
        bool max_error = false, ratio = false;
        std::vector<SpecKey> keys = {
            {"max-error", [&](const std::string& v, const std::string& what) {
               options.max_error = float(spec_number_or_usage(v, what, 1e-5, 0.1));
               max_error = true;
             }},
            {"ratio", [&](const std::string& v, const std::string& what) {
               options.ratio = float(spec_number_or_usage(v, what, 1.0, 1e6));
               ratio = true;
             }},
            number_key("normal-bits", options.normal_bits, 6, 14)};
        bool strict_given = false;
        if (strict) keys.push_back(flag_key("strict", strict_given));
        parse_spec("--codec", spec, keys, &name);
        if (std::find(allowed.begin(), allowed.end(), name) == allowed.end()) {
          std::string k;
          for (const auto& a : allowed) k += (k.empty() ? "" : ", ") + a;
          throw UsageError("--codec: '" + name + "' is not a codec (" + k + ")");
        }
        if (max_error && ratio) throw UsageError("--codec: max-error and ratio exclude each other (give one)");
        if (strict) *strict = strict_given;
        if (bound_given) *bound_given = max_error || ratio;
        codec = name;
      },
      help);
}

CLI::Option* add_codec_bound_options(CLI::App& cmd, CodecOptions& options, bool* strict) {
  if (strict) cmd.add_flag("--strict", *strict, "With --ratio: fail (exit 1) when the codec cannot reach the ratio");
  auto* max_error = cmd.add_option("--max-error", options.max_error,
                                   "Bound on |t1 - t0| / box diagonal for every hit sample")
                        ->check(finite_range(1e-5, 0.1))
                        ->capture_default_str();
  auto* ratio = cmd.add_option("--ratio", options.ratio,
                               "Target compression ratio (finds the tightest bound reaching it)")
                    ->check(finite_range(1.0, 1e6));
  max_error->excludes(ratio);
  cmd.add_option("--normal-bits", options.normal_bits, "Octahedral normal bits per coordinate")
      ->check(CLI::Range(6, 14))
      ->capture_default_str();
  return max_error;
}

} // namespace hb::cli
