#pragma once
// Never slower than exact along strokes (budgeted bake step 7): a scene the surface
// cells answer on a simplified surface is timed along hand-like strokes, one probe with its
// query state as a servo loop asks, against exact Embree over the full mesh; where Embree is
// faster there it answers the scene's strokes (SceneParts::stroke), and the cells keep
// the queries without a state (random, batched), where they are faster.
#include "contact/contact.h"
#include "scene/box_scene.h"
#include "mesh/triangle_mesh.h"
#include <cstdint>

namespace hb {

/// The most triangles a stroke route is built over: Embree's build runs at every load (about
/// 1.1 s a million triangles here), and at 13M triangles the cells are 1.9x faster along
/// strokes anyway (docs/speed.md).
constexpr std::uint64_t kStrokeMeshMaxTriangles = 2'000'000;

/// For a scene the cells answer (others are left as they are): times it along 10 strokes of
/// 500 ticks (sample_strokes, `seed`) through a SceneProbe against the same scene with the
/// stroke route over `mesh` (the full mesh, with its vertex normals), paired batches on the
/// calling thread: Embree over the full mesh answers the strokes unless the cells are clearly
/// faster there (recipe/route_rule.h). Records the choice and both times in `report`
/// (stroke_answer, stroke_cells_ns, stroke_embree_ns); a mesh over kStrokeMeshMaxTriangles is
/// not timed (stroke_answer "cells").
void choose_stroke_route(BoxScene& scene, const TriangleMesh& mesh, const ForceLaw& law, std::uint64_t seed,
                         BudgetReport& report);

} // namespace hb
