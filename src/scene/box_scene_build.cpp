// Making a box scene (box_scene.h): the constructor (the shared surface, its surface cells,
// the boxes' bounds), the routes (the Embree route over the surface), the scenes derived from
// one (without triangle ids, compressed) and the memory figures. The query is box_scene.cpp's.
#include "scene/box_scene_parts.h"
#include "errors.h"
#include "geometry/octahedral.h"
#include <cstring>
#include <mutex>
#include <unordered_map>

namespace hb {

namespace {
// The surface cells of a grid and a surface: built once for the pair however many scenes hold
// them (a budgeted bake composes three or more; at 13M triangles each build takes seconds).
// Both are immutable once built; the last pair's cells are kept while something holds them,
// and weak pointers make sure the pair is the same objects, not new ones at old addresses.
std::shared_ptr<const SurfaceCells> surface_cells_of(const std::shared_ptr<const SceneGrid>& grid,
                                                     const std::shared_ptr<const SurfaceTriangles>& surface) {
  static std::mutex mutex;
  static std::weak_ptr<const SceneGrid> last_grid;
  static std::weak_ptr<const SurfaceTriangles> last_surface;
  static std::weak_ptr<const SurfaceCells> last_cells;
  {
    std::lock_guard<std::mutex> lock(mutex);
    if (last_grid.lock() == grid && last_surface.lock() == surface)
      if (auto cells = last_cells.lock()) return cells;
  }
  auto cells = std::make_shared<const SurfaceCells>(*grid, surface);
  std::lock_guard<std::mutex> lock(mutex);
  last_grid = grid;
  last_surface = surface;
  last_cells = cells;
  return cells;
}
} // namespace

namespace {
void check_piece_ids(const std::vector<std::uint32_t>& piece_of_triangle, std::size_t boxes) {
  for (std::uint32_t id : piece_of_triangle)
    if (id >= boxes)
      throw InvalidInput("box scene: piece id " + std::to_string(id) + " but " + std::to_string(boxes) + " boxes");
}
} // namespace

BoxScene::BoxScene(SceneParts parts) : parts_(std::move(parts)) {
  SceneParts& p = parts_;
  check_piece_ids(p.piece_of_triangle, p.boxes.size());
  if (p.grid && p.grid->empty()) p.grid.reset();
  if (p.grid && p.grid->list_count() > 0 && p.grid->max_box() >= p.boxes.size())
    throw InvalidInput("box scene: the scene grid names box " + std::to_string(p.grid->max_box()) + ", the scene has " +
                       std::to_string(p.boxes.size()));
  // The surface the refining boxes share (or the one given), and the triangles below the
  // grid's surface cells from it.
  bool shared = true;
  const bool given = p.surface != nullptr;
  for (const HapticBox& box : p.boxes)
    if (box.refines()) {
      if (given && p.surface != box.surface())
        throw InvalidInput("box scene: a box refines against another surface than the scene's");
      if (p.surface && p.surface != box.surface()) shared = false;
      p.surface = box.surface();
    }
  if (!shared) p.surface.reset();
  if (p.grid && p.surface) cells_ = surface_cells_of(p.grid, p.surface);
  for (auto& b : bounds_) b.reserve(p.boxes.size());
  for (const HapticBox& box : p.boxes) {
    const Obb& o = box.obb();
    // Half extents of the OBB along world axes: |R| * half.
    const Vec3 extent = o.axes.cwiseAbs() * o.half;
    for (int a = 0; a < 3; ++a) {
      bounds_[a].push_back(o.center[a] - extent[a]);
      bounds_[3 + a].push_back(o.center[a] + extent[a]);
    }
  }
  // The route, once: Embree over the surface when asked (its tree built unless the parts
  // carry it), the cells when there are surface cells, the boxes otherwise.
  if (p.route == SceneRoute::embree) {
    if (!p.surface) throw InvalidInput("box scene: the embree route needs the scene's surface (this scene has none)");
    if (p.surface->normal_map_side() > 0)
      throw InvalidInput("box scene: the embree route needs the full surface; this one is simplified (a normal map shades it)");
    if (!p.embree || p.embree->over != p.surface) p.embree = std::make_shared<const SceneEmbree>(p.surface);
    route_ = SceneRoute::embree;
  } else {
    route_ = p.route == SceneRoute::cells && cells_ ? SceneRoute::cells : SceneRoute::boxes;
  }
  if (route_ == SceneRoute::boxes && !has_tables(p))
    throw InvalidInput(std::string("box scene: the ") + route_name(p.route) +
                       " route leaves the boxes to answer, and they are frames without tables (the bake answered "
                       "this scene by exact Embree)");
  stroke_route_ = p.stroke && route_ == SceneRoute::cells ? SceneRoute::embree : route_;
}

SceneEmbree::SceneEmbree(std::shared_ptr<const SurfaceTriangles> surface_ptr) : over(std::move(surface_ptr)) {
  const SurfaceTriangles& surface = *over;
  const std::size_t n = surface.size();
  mesh.positions.reserve(n);
  mesh.normals.reserve(n);
  mesh.triangles.reserve(n);
  struct Key {
    std::uint32_t x, y, z, normal;
    bool operator==(const Key& o) const { return x == o.x && y == o.y && z == o.z && normal == o.normal; }
  };
  struct KeyHash {
    std::size_t operator()(const Key& k) const noexcept {
      std::uint64_t h = k.x * 0x9E3779B97F4A7C15ull;
      h ^= (h >> 29) ^ (k.y * 0xBF58476D1CE4E5B9ull);
      h ^= (h >> 31) ^ (k.z * 0x94D049BB133111EBull);
      return std::size_t(h ^ (h >> 30) ^ k.normal);
    }
  };
  std::unordered_map<Key, std::uint32_t, KeyHash> index;
  index.reserve(n);
  const auto vertex = [&](const Vec3& p, std::uint32_t normal) {
    Key k{0, 0, 0, normal};
    std::memcpy(&k.x, &p.x(), 4), std::memcpy(&k.y, &p.y(), 4), std::memcpy(&k.z, &p.z(), 4);
    const auto [it, added] = index.emplace(k, std::uint32_t(mesh.positions.size()));
    if (added) {
      mesh.positions.push_back(p);
      mesh.normals.push_back(decode_octahedral32(normal));
    }
    return it->second;
  };
  const SurfaceTriangles::Record* r = surface.records();
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 a(r[i].a[0], r[i].a[1], r[i].a[2]);
    const Vec3 e1(r[i].e1[0], r[i].e1[1], r[i].e1[2]), e2(r[i].e2[0], r[i].e2[1], r[i].e2[2]);
    mesh.triangles.push_back({vertex(a, r[i].normal[0]), vertex(a + e1, r[i].normal[1]), vertex(a + e2, r[i].normal[2])});
  }
  exact = std::make_unique<ExactQuery>(mesh);
}

SceneEmbree::SceneEmbree(TriangleMesh full) : mesh(std::move(full)) {
  if (mesh.triangles.empty()) throw InvalidInput("box scene: the stroke route's mesh has no triangles");
  if (mesh.normals.size() != mesh.positions.size())
    throw InvalidInput("box scene: the stroke route's mesh has " + std::to_string(mesh.normals.size()) +
                       " vertex normals for " + std::to_string(mesh.positions.size()) + " vertices");
  exact = std::make_unique<ExactQuery>(mesh);
}

SceneEmbree::~SceneEmbree() = default;

std::shared_ptr<const SceneEmbree> make_stroke_route(TriangleMesh mesh) {
  return std::make_shared<const SceneEmbree>(std::move(mesh));
}

bool has_triangle_ids(const SceneParts& parts) noexcept {
  for (const HapticBox& b : parts.boxes)
    if (b.refines()) return true;
  return false;
}

bool has_tables(const SceneParts& parts) noexcept {
  for (const HapticBox& b : parts.boxes)
    if (!b.has_table()) return false;
  return true;
}

SceneBytes BoxScene::bytes() const noexcept {
  const SceneParts& p = parts_;
  SceneBytes b;
  for (const HapticBox& box : p.boxes) b.tables += box.table_bytes();
  b.refinement = p.surface ? p.surface->bytes() : 0;
  const SurfaceTriangles* counted = p.surface.get();
  for (const HapticBox& box : p.boxes) {
    b.refinement += box.triangle_id_bytes();
    if (!p.surface && box.refines() && box.surface().get() != counted) {  // boxes on different surfaces
      counted = box.surface().get();
      b.refinement += counted->bytes();
    }
  }
  for (const SceneEmbree* r : {route_ == SceneRoute::embree ? p.embree.get() : nullptr, p.stroke.get()})
    if (r) b.embree += r->mesh.positions.size() * 2 * sizeof(Vec3) + r->mesh.triangles.size() * 12;
  b.memory = b.tables + b.refinement + (p.surface ? p.surface->normal_map_bytes() : 0) + (p.grid ? p.grid->bytes() : 0) +
             (cells_ ? cells_->bytes() : 0) + b.embree;
  return b;
}

Answerer answerer(const BoxScene& scene) noexcept {
  return answerer_of(scene.route(), scene.refines());
}

SceneParts without_tables(const BoxScene& scene) {
  SceneParts p = scene.parts();
  for (HapticBox& b : p.boxes) b = b.frame();
  p.route = SceneRoute::embree;
  return p;
}

SceneParts without_triangle_ids(const BoxScene& scene) {
  SceneParts p = scene.parts();
  if (!scene.cells()) return p;
  for (HapticBox& b : p.boxes) b = b.without_refinement();
  return p;
}

SceneParts compressed(const BoxScene& scene, const CodecOptions& options) {
  SceneParts p = scene.parts();
  for (HapticBox& b : p.boxes) b = b.compressed(options);
  return p;
}

BoxScene with_budget(const BoxScene& scene, BudgetReport budget) {
  SceneParts p = scene.parts();
  p.budget = std::move(budget);
  return BoxScene(std::move(p));
}

BoxScene with_route(const BoxScene& scene, SceneRoute route) {
  SceneParts p = scene.parts();
  p.route = route;
  return BoxScene(std::move(p));
}

} // namespace hb
