#pragma once
// Seams between pieces: which triangles each piece's box is baked from.
#include "mesh/triangle_mesh.h"
#include <cstdint>
#include <vector>

namespace hb {

/// The triangle lists to bake, one per piece, from a piece id per triangle: each piece is
/// grown by `seam_rings` rings of edge-neighbouring triangles of other pieces, so the seam
/// triangles belong to both boxes.
///
/// Why overlap: a box stores only its own piece, cut open at the seam. A probe entering
/// near the seam meets, in the box of piece A, samples that pass through the cut (a back
/// face or a miss) next to samples that hit A; interpolation puts A's edge half a sample
/// short of the seam, and piece B's box does the same from the other side, so without
/// overlap a probe crossing the seam can fall into a gap between the two. With one or two
/// shared rings both boxes cover the seam, and the scene's rule (the valid contact nearest
/// the handle wins) picks one answer where both report a contact.
///
/// `piece_of_triangle[t]` in 0..K-1 (ids absent from the list give empty pieces, which are
/// dropped; the result is in id order). seam_rings >= 0 (0: disjoint pieces). An empty
/// `piece_of_triangle` means one piece of all triangles. Throws hb::InvalidInput when the
/// list's size differs from the triangle count.
std::vector<std::vector<std::uint32_t>> piece_triangle_lists(const TriangleMesh& mesh,
                                                             const std::vector<std::uint32_t>& piece_of_triangle,
                                                             int seam_rings = 1);

} // namespace hb
