#pragma once
// The default probe distribution used by eval, bench, sweep and reports, so figures compare.
#include "geometry/segment.h"
#include "mesh/triangle_mesh.h"
#include <cstdint>
#include <vector>

namespace hb {

/// Options of sample_probes. Lengths are fractions of the mesh's bounding-box diagonal.
struct ProbeOptions {
  float cone_degrees = 30.f;        ///< max angle between the probe direction and the inward normal.
  float length_fraction = 0.10f;    ///< segment length.
  float max_depth_fraction = 0.03f; ///< tip depth past the surface point, uniform in [0, this].
  std::uint64_t seed = 1;           ///< same seed, same mesh: same probes.
};

/// A light touch at any angle: within 85 degrees of the inward normal, tips up to 0.5% of the
/// diagonal past the surface (under 0.6 N at the default workspace). The default probes
/// (within 30 degrees, up to 3% deep: 1-3 N) do not show a box's error along lines far from
/// the normal at a touch light enough to feel it (a raw box's lines 37-53 degrees off the
/// normal can be 0.03-0.1 mm off, felt at such a touch but not at 1-3 N). `eval` reports
/// both.
inline ProbeOptions light_touch_probe_options(std::uint64_t seed) {
  ProbeOptions o;
  o.cone_degrees = 85.f;
  o.max_depth_fraction = 0.005f;
  o.seed = seed;
  return o;
}

/// Samples probes: tip near a surface point chosen by area (uniform over the surface), the
/// direction within the cone around the inward (flat) normal, the tip past the surface point
/// by a uniform depth along the direction, the handle one segment length back.
/// Deterministic for a given seed. Throws hb::InvalidInput on an empty mesh.
std::vector<Segment> sample_probes(const TriangleMesh& mesh, std::size_t count, const ProbeOptions& options = {});

/// Hand-like strokes, the probe sequence a 1 kHz servo loop sees: for each of `strokes`
/// probes of sample_probes (the anchors), `steps` probes with the anchor's direction whose
/// handle and tip move once around a circle of radius `radius_fraction` x the mesh diagonal,
/// perpendicular to the direction (the tip glides over the surface at constant depth below the
/// anchor's plane). In stroke order, `steps` consecutive probes per stroke. Throws
/// hb::InvalidInput on an empty mesh or steps < 1.
std::vector<Segment> sample_strokes(const TriangleMesh& mesh, std::size_t strokes, std::size_t steps,
                                    float radius_fraction, const ProbeOptions& options = {});

/// Reorders probes along a space-filling (Morton) curve through their tips, so consecutive
/// probes are close in space, as along a hand's trajectory: the coherent case of `bench`.
void sort_probes_coherently(std::vector<Segment>& probes);

} // namespace hb
