#pragma once
// A STEP (ISO 10303-21) file's instance references checked before OpenCASCADE reads it: every
// "#N" an entity refers to is defined once in the DATA section (a reference to a missing
// instance, or "#0", crashed OpenCASCADE's translator: a segmentation fault, not an
// exception). Pure function over bytes (no file access).
#include <string>

namespace hb {

/// Deepest parenthesis nesting accepted in a STEP statement (real files nest a few levels).
constexpr long kMaxStepNesting = 100;

/// Throws hb::InvalidInput naming `name`, the referring instance and the missing one (or the
/// instance defined twice, an unterminated string or comment, parentheses unbalanced or nested
/// deeper than kMaxStepNesting, no DATA section).
void check_step_references(const std::string& name, const std::string& bytes);

} // namespace hb
