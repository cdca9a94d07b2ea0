#pragma once
// Manual decomposition files: a piece id per triangle (paper section 4.1 decomposes by hand).
#include "mesh/triangle_mesh.h"
#include <cstdint>
#include <string>
#include <vector>

namespace hb {

/// Reads a piece id per triangle of a mesh with `triangle_count` triangles.
///  - `.txt` (or any other extension): plain text, one non-negative integer id per line, in
///    triangle order; blank lines and lines starting with '#' are ignored.
///  - `.ply`: the face element's integer property named `piece` (or, failing that, `label`,
///    `segment`, `part`, `region`), ASCII or binary PLY. A face of k corners stands for the
///    k - 2 triangles the mesh reader makes of it, in order.
/// Ids need not be contiguous (empty ids are dropped when baking).
/// Throws hb::IoError (missing, unreadable, truncated) or hb::InvalidInput (not a number, a
/// negative id, count differing from `triangle_count`, no piece property); messages name the
/// file, and the line or face where possible.
std::vector<std::uint32_t> read_piece_file(const std::string& path, std::size_t triangle_count);

/// Writes a piece id per triangle: `.ply` writes the mesh with a face property `piece` and a
/// face colour per piece (for viewers); any other extension writes the plain-text form.
/// Throws hb::IoError, or hb::InvalidInput when the sizes differ.
void write_piece_file(const std::string& path, const TriangleMesh& mesh,
                      const std::vector<std::uint32_t>& piece_of_triangle);

} // namespace hb
