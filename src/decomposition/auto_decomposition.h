#pragma once
// Automatic decomposition into quasi-convex pieces (the paper's future work, section 7:
// "build an OBB tree and merge from bottom up around the leaf nodes according to some
// quasi-convexity parameters").
#include "mesh/triangle_mesh.h"
#include "progress.h"
#include <cstdint>
#include <vector>

namespace hb {

class EmbreeScene;

/// Options of decompose_auto. Defaults work on the CGAL datasets and the generators.
struct AutoDecompositionOptions {
  /// Largest pocket probability (see PocketScore) a merged piece may have, in [0, 1].
  /// Lower: more, smaller pieces and fewer hidden contacts. Measured on the armadillo (52K
  /// triangles, m=32 n=16, 20K probes): 0.004 gives 6 pieces (0.9 GB of tables, 96.4%
  /// contact agreement), 0.001 gives 37 pieces (5.6 GB, 99.1%); one box: 90.5%.
  /// The chess piece gives 5 pieces at 0.004.
  double threshold = 0.004;
  /// Pieces with less than this fraction of the total surface area are merged into their
  /// best neighbour even above the threshold, in [0, 1).
  double min_area_fraction = 0.002;
  /// Upper bound on the piece count, >= 1; merging continues above the threshold (cheapest
  /// first) until it holds. Each piece costs one box of memory.
  int max_pieces = 32;
  /// Target number of leaf clusters of the OBB-style tree (leaves are also split into
  /// connected components), >= 1. More: finer seams, slower.
  int leaves = 768;
  /// Isotropic random lines through the mesh's bounding sphere used to estimate pocket
  /// probabilities of candidate merges, >= 1000. More: less noise on small pieces, slower.
  int lines = 300000;
  std::uint64_t seed = 1;  ///< same mesh, same options, same seed: same pieces.
  /// Progress in [0, 1]; return false to cancel (throws hb::Cancelled).
  ProgressCallback progress;
  /// Called at the end of each phase (clusters, lines, pieces, merged) with the seconds since
  /// the start: a diagnostic for large meshes (`HB_MEASURE=decompose-times`); may be empty.
  std::function<void(const char* phase, double seconds)> on_phase;
};

/// The result: a piece id per triangle (0..piece_count-1, numbered in order of each piece's
/// lowest triangle id) and the line-set estimate of each piece's pocket probability.
struct Decomposition {
  std::vector<std::uint32_t> piece_of_triangle;
  std::size_t piece_count = 0;
  std::vector<double> estimated_probability;  ///< per piece, from the shared line set.
};

/// Decomposes `mesh` into quasi-convex pieces:
///  1. an OBB-style tree (median splits along the longest axis) down to ~options.leaves
///     leaves, each split into edge-connected components: the initial clusters;
///  2. one set of isotropic lines through the whole mesh with all their surface crossings
///     (Embree), which gives the pocket length of any union of clusters along every line;
///  3. greedy bottom-up merging of edge-adjacent pieces, the merge with the lowest pocket
///     probability (ties: the smaller union) first, while it stays <= threshold;
///  4. small pieces merged into a neighbour, then the cheapest merges until max_pieces.
/// Pieces do not overlap here: bake with seam rings (piece_triangle_lists) to share seam
/// triangles. Deterministic on any thread count. Throws hb::InvalidInput (empty mesh, bad
/// options), hb::Cancelled, hb::LibraryError.
/// `scene`, when given, is an Embree scene of all of `mesh`'s triangles (in mesh order) to cast
/// the lines against instead of building one: on 13M triangles a BVH build is seconds, and the
/// budgeted bake has already built one for its exact answers. The pieces are the same.
Decomposition decompose_auto(const TriangleMesh& mesh, const AutoDecompositionOptions& options = {},
                             const EmbreeScene* scene = nullptr);

} // namespace hb
