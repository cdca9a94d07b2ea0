#pragma once
// Options given as "[head,]key=value,key,...": the usage error they throw, the grammar that
// reads them (hb::parse_spec_keys: keys in any order, any subset) and the keys that set a number or
// a flag.
#include "spec_parse.h"
#include <CLI/CLI.hpp>
#include <functional>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

namespace hb::cli {

/// Thrown by a command for a usage error the parser could not catch (exit code 2).
class UsageError : public std::runtime_error {
public:
  explicit UsageError(const std::string& what) : std::runtime_error(what) {}
};

/// Validator of a numeric option: a finite number in [lo, hi] (CLI::Range lets "nan" through,
/// since no comparison with NaN fails). The message names the value and the range.
CLI::Validator finite_range(double lo, double hi);

/// One key of a spec option ("--codec block,ratio=20,strict"): hb::SpecKey (spec_parse.h).
using SpecKey = hb::SpecKey;
/// hb::parse_spec_keys (the grammar both front ends share), its errors UsageErrors (exit 2): the
/// unknown key (with the known ones) or the bad value.
void parse_spec(const std::string& option, const std::string& spec, const std::vector<SpecKey>& keys,
                std::string* head = nullptr);
/// hb::spec_number, its hb::InvalidInput a UsageError.
double spec_number_or_usage(const std::string& text, const std::string& what, double lo, double hi);
/// A key setting a number in [lo, hi] (integers for integral fields).
template <class T>
SpecKey number_key(const std::string& key, T& field, double lo, double hi) {
  return {key, [&field, lo, hi](const std::string& v, const std::string& what) {
            const double x = spec_number_or_usage(v, what, lo, hi);
            if (std::is_integral<T>::value && x != double(static_cast<long long>(x)))
              throw UsageError(what + ": '" + v + "' is not a whole number");
            field = static_cast<T>(x);
          }};
}
/// A key setting a flag: bare or =1/on/yes true, =0/off/no false.
SpecKey flag_key(const std::string& key, bool& field);

} // namespace hb::cli
