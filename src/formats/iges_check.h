#pragma once
// An IGES file's structure checked before OpenCASCADE reads it: its reader trusts the
// directory entries' parameter pointers, the pointers between entities and the counts inside
// the parameter data, and a damaged one was a segmentation fault in the translator (about a
// quarter of the mutation campaign's damaged IGES files), not an exception. Pure function over
// bytes (no file access): a fuzz target can run it under the sanitizers.
#include <string>

namespace hb {

/// Checks, in order: every line has its section letter in column 73 (S, G, D, P, T in that
/// order, one T line last) and its sequence number in columns 74-80; the T line's counts
/// equal the sections' lengths; the directory entries come in pairs whose fields are
/// integers, whose entity type is the same on both lines, whose parameter lines lie within
/// the P section and carry the entry's number in columns 66-72, and whose pointers
/// (structure, line font, level, view, transformation, label display, colour) are 0 or an
/// entry (a transformation a type 124); every entry's parameter data starts with its type and
/// ends with the record delimiter; for the entities of solids and surfaces (100, 102, 110,
/// 116, 123, 124, 142, 144, 186, 190, 192, 194, 196, 502, 504, 508, 510, 514) the
/// counts agree with the parameters present, the numbers are numbers, the pointers refer to
/// entries of a fitting type and the list indices lie within their lists; B-splines (126,
/// 128) hold numbers only, and when their counts fit, knots that never decrease and positive
/// weights. Every line is text (no control byte).
/// Throws hb::InvalidInput naming `name`, the line or the directory entry (by its sequence
/// number, as IGES tools name them) and the cause.
void check_iges_structure(const std::string& name, const std::string& bytes);

} // namespace hb
