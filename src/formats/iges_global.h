#pragma once
// The global section of an IGES file, checked before OpenCASCADE reads it: OpenCASCADE falls
// back to inches when the section does not parse, and follows the unit flag (field 14) even
// when the unit name (field 15) says otherwise, so a damaged section rescaled a model by 25.4
// (or 1/1000) without a word. Pure functions over bytes (no file access): a fuzz target can
// run them under the sanitizers.
#include <string>
#include <vector>

namespace hb {

/// The global section's fields (the G lines' columns 1-72 joined, Hollerith strings nH...
/// decoded, the parameter and record delimiters of fields 1 and 2 honoured), in order.
/// Throws hb::InvalidInput naming `name` when there is no G line, a Hollerith string runs
/// past the section, or the record delimiter never comes.
std::vector<std::string> parse_iges_global(const std::string& name, const std::string& bytes);

/// The length unit the global section declares, in millimetres per model unit: the unit flag
/// (field 14, 1 to 11) and the unit name (field 15) must agree (flag 3 takes its unit from the
/// name). Throws hb::InvalidInput naming `name` and the field otherwise.
double iges_mm_per_unit(const std::string& name, const std::string& bytes);

} // namespace hb
