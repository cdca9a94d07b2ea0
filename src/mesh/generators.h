#pragma once
// Procedural test objects: the paper's bumpy sphere and chess piece, and analytic shapes for tests.
#include "mesh/triangle_mesh.h"

namespace hb {

/// Options of make_bumpy_sphere.
struct BumpySphereOptions {
  float radius = 1.f;           ///< mean radius, model units, > 0.
  float bump_amplitude = 0.06f; ///< relative radial amplitude of the bumps, in [0, 0.3].
  int bump_frequency = 6;       ///< number of bumps around a great circle, >= 1.
  int subdivisions = 7;         ///< icosphere subdivision level: 20 * 4^s triangles (7: 327,680).
};

/// Quasi-convex bumpy sphere (paper section 6): an icosphere with smooth radial bumps.
TriangleMesh make_bumpy_sphere(const BumpySphereOptions& options = {});

/// Options of make_chess_piece.
struct ChessPieceOptions {
  float height = 1.f;        ///< model units, > 0.
  int profile_samples = 400; ///< samples along the profile curve, >= 8.
  int segments = 256;        ///< samples around the axis, >= 8.
};

/// A chess piece (pawn/queen-like surface of revolution about +Z, closed by caps) whose
/// profile has several necks and bulges, so it needs several quasi-convex pieces.
/// Default options give at least 100,000 triangles.
TriangleMesh make_chess_piece(const ChessPieceOptions& options = {});

/// Icosphere of the given radius (20 * 4^subdivisions triangles), centred at the origin.
TriangleMesh make_sphere(float radius, int subdivisions);

/// Axis-aligned box with half extents `half`, centred at the origin, each face split into
/// `divisions` x `divisions` quads (2 triangles each).
TriangleMesh make_cube(const Vec3& half, int divisions = 1);

/// Ellipsoid with semi-axes `radii` (a scaled icosphere).
TriangleMesh make_ellipsoid(const Vec3& radii, int subdivisions);

/// Torus about +Z with major radius R and minor radius r.
TriangleMesh make_torus(float major_radius, float minor_radius, int major_segments, int minor_segments);

} // namespace hb
