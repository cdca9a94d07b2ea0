#pragma once
// How far a simplified surface (hb::decimate) is from the full one, measured, and the
// simplified surface's shading fitted to the full one's.
#include "mesh/triangle_mesh.h"
#include <cstddef>
#include <cstdint>
#include <vector>

namespace hb {

class EmbreeScene;

/// Distances from the full surface to the simplified one (model units), and the angles
/// between their shaded normals there (degrees).
struct SurfaceDeviation {
  std::size_t samples = 0;
  double mean = 0.0, p99 = 0.0, max = 0.0;
  /// Angle between the full mesh's shaded normal at the sample and the simplified mesh's
  /// shaded normal where the sample's normal line meets it (samples that meet it only).
  double normal_median_deg = 0.0, normal_p95_deg = 0.0, normal_p99_deg = 0.0;
};

/// From `samples` points on `full` (uniform by area, seed `seed`), the distance along the
/// full mesh's flat normal, both ways, to `simplified` (Embree rays from `cap` behind the
/// point on either side; no hit within `cap` counts as cap: keep it below the thinnest part). Distances along the normal are at least the closest-point distances, so the figures
/// over-state the deviation. On all cores. Throws hb::InvalidInput on an empty mesh.
SurfaceDeviation measure_deviation(const TriangleMesh& full, const TriangleMesh& simplified, std::size_t samples,
                                   double cap, std::uint64_t seed = 7);

/// What fit_shading() did.
struct ShadingFitStats {
  std::size_t triangles = 0;  ///< triangles of the simplified surface.
  std::size_t fitted = 0;     ///< of them, those whose corner normals were fitted (the rest keep their vertex normals).
  double seconds = 0.0;
};

/// The simplified surface with its shading fitted to the full mesh's: each triangle of
/// `simplified` gets three vertices of its own (same positions, same triangle order, so
/// triangle ids and the welded-by-position neighbours of SurfaceTriangles are unchanged)
/// whose normals are the least-squares fit, over a barycentric grid of `grid` steps a side,
/// of the full mesh's shaded normal where the triangle's normal line through the grid point
/// meets the full mesh (within `cap`, the nearest hit facing the same way). The exact answer
/// shades with the full mesh's normals; a simplified triangle that spans many of its
/// triangles (a flat-subdivided mesh's faceted shading, a curved region) then interpolates
/// the shading that region has rather than the normals of the kept vertices. A triangle
/// with fewer than 3 grid points met keeps its vertex normals. On all cores. Throws
/// hb::InvalidInput on an empty mesh, a simplified mesh without normals or grid < 1.
TriangleMesh fit_shading(const TriangleMesh& full, const TriangleMesh& simplified, double cap, int grid = 6,
                         ShadingFitStats* stats = nullptr);

/// The normal map (SurfaceTriangles::set_normal_map) that shades `simplified` as `full`
/// shades: per triangle of `simplified` (mesh order, from its corner 0, u along corner 1 and v
/// along corner 2), the (side + 1)(side + 2) / 2 points of the barycentric lattice of `side`
/// steps, row j after row j - 1, each the octahedral32 code of the full mesh's shaded normal
/// where the triangle's normal line through the point meets it (within `cap`, the nearest
/// hit facing the same way), or else of `simplified`'s vertex normals interpolated there.
/// Where `simplified` is a coarser mesh that `full` flat-subdivides log2(side) times, every
/// lattice point is a vertex of `full` and the map reproduces its shading. `scene`, when
/// given, is an EmbreeScene of `full` (else one is built). On all cores. Throws
/// hb::InvalidInput on an empty mesh, missing normals or a side outside [1, 64].
std::vector<std::uint32_t> fit_normal_map(const TriangleMesh& full, const TriangleMesh& simplified, int side,
                                          double cap, const EmbreeScene* scene = nullptr,
                                          ShadingFitStats* stats = nullptr);

} // namespace hb
