// The stroke route's choice (stroke_route.h).
#include "recipe/stroke_route.h"
#include "recipe/route_rule.h"
#include "evaluation/probe_sampling.h"
#include "evaluation/query_timing.h"
#include <utility>
#include <vector>

namespace hb {

void choose_stroke_route(BoxScene& scene, const TriangleMesh& mesh, const ForceLaw& law, std::uint64_t seed,
                         BudgetReport& report) {
  if (scene.route() != SceneRoute::cells) return;
  report.stroke_answer = Answerer::cells;
  if (mesh.triangle_count() > kStrokeMeshMaxTriangles || mesh.normals.size() != mesh.positions.size()) return;
  SceneParts parts = scene.parts();
  parts.stroke = make_stroke_route(mesh);
  BoxScene by_embree(std::move(parts));
  ProbeOptions options;
  options.seed = seed;
  const std::vector<Segment> strokes = sample_strokes(mesh, 10, 500, 0.02f, options);
  const SceneProbe cells(scene), embree(by_embree);
  const PairedTiming t = paired_query_ns(cells, embree, strokes, law);
  report.stroke_cells_ns = t.a_ns;
  report.stroke_embree_ns = t.b_ns;
  if (!clearly_faster_than_embree(t.a_ns, t.b_ns)) {
    report.stroke_answer = Answerer::embree;
    scene = std::move(by_embree);
  }
}

} // namespace hb
