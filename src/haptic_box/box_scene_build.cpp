// Making a box scene (box_scene.h): the constructor (the shared surface, its surface cells,
// the boxes' bounds), the routes (the Embree route over the surface), the scenes derived from
// one (without triangle ids, compressed) and the memory figures. The query is box_scene.cpp's.
#include "haptic_box/box_scene_parts.h"
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

BoxScene::BoxScene(std::vector<HapticBox> boxes, SourceInfo source, std::vector<std::uint32_t> piece_of_triangle,
                   std::shared_ptr<const SceneGrid> grid, std::shared_ptr<const SurfaceTriangles> surface)
    : boxes_(std::move(boxes)), source_(std::move(source)), grid_(std::move(grid)), surface_(std::move(surface)) {
  set_piece_of_triangle(std::move(piece_of_triangle));
  if (grid_ && grid_->empty()) grid_.reset();
  if (grid_ && grid_->list_count() > 0 && grid_->max_box() >= boxes_.size())
    throw InvalidInput("box scene: the scene grid names box " + std::to_string(grid_->max_box()) + ", the scene has " +
                       std::to_string(boxes_.size()));
  // The surface the refining boxes share (or the one given), and the triangles below the
  // grid's surface cells from it.
  bool shared = true;
  const bool given = surface_ != nullptr;
  for (const HapticBox& box : boxes_)
    if (box.refines()) {
      if (given && surface_ != box.surface())
        throw InvalidInput("box scene: a box refines against another surface than the scene's");
      if (surface_ && surface_ != box.surface()) shared = false;
      surface_ = box.surface();
    }
  if (!shared) surface_.reset();
  if (grid_ && surface_) cells_ = surface_cells_of(grid_, surface_);
  for (auto& b : bounds_) b.reserve(boxes_.size());
  for (const HapticBox& box : boxes_) {
    const Obb& o = box.obb();
    // Half extents of the OBB along world axes: |R| * half.
    const Vec3 extent = o.axes.cwiseAbs() * o.half;
    for (int a = 0; a < 3; ++a) {
      bounds_[a].push_back(o.center[a] - extent[a]);
      bounds_[3 + a].push_back(o.center[a] + extent[a]);
    }
  }
}

BoxScene::EmbreeRoute::EmbreeRoute(const SurfaceTriangles& surface) {
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

BoxScene::EmbreeRoute::EmbreeRoute(TriangleMesh full) : mesh(std::move(full)) {
  if (mesh.triangles.empty()) throw InvalidInput("box scene: the stroke route's mesh has no triangles");
  if (mesh.normals.size() != mesh.positions.size())
    throw InvalidInput("box scene: the stroke route's mesh has " + std::to_string(mesh.normals.size()) +
                       " vertex normals for " + std::to_string(mesh.positions.size()) + " vertices");
  exact = std::make_unique<ExactQuery>(mesh);
}

void BoxScene::set_stroke_mesh(TriangleMesh mesh) { stroke_ = std::make_shared<const EmbreeRoute>(std::move(mesh)); }

const TriangleMesh* BoxScene::stroke_mesh() const noexcept { return stroke_ ? &stroke_->mesh : nullptr; }

void BoxScene::set_route(SceneRoute route) {
  if (route == SceneRoute::embree && !embree_) {
    if (!surface_) throw InvalidInput("box scene: the embree route needs the scene's surface (this scene has none)");
    if (surface_->normal_map_side() > 0)
      throw InvalidInput("box scene: the embree route needs the full surface; this one is simplified (a normal map shades it)");
    embree_ = std::make_shared<const EmbreeRoute>(*surface_);
  }
  const SceneRoute before = route_;
  route_ = route;
  if (answering_route() == SceneRoute::boxes && !has_tables()) {
    route_ = before;
    throw InvalidInput(std::string("box scene: the ") + route_name(route) +
                       " route leaves the boxes to answer, and they are frames without tables (the bake answered "
                       "this scene by exact Embree)");
  }
}

std::size_t BoxScene::embree_bytes() const noexcept {
  std::size_t bytes = 0;
  for (const EmbreeRoute* r : {embree_.get(), stroke_.get()})
    if (r) bytes += r->mesh.positions.size() * 2 * sizeof(Vec3) + r->mesh.triangles.size() * 12;
  return bytes;
}

bool BoxScene::has_triangle_ids() const noexcept {
  for (const HapticBox& b : boxes_)
    if (b.refines()) return true;
  return false;
}

bool BoxScene::has_tables() const noexcept {
  for (const HapticBox& b : boxes_)
    if (!b.has_table()) return false;
  return true;
}

BoxScene BoxScene::with_boxes(std::vector<HapticBox> boxes) const {
  BoxScene s(std::move(boxes), source_, piece_of_triangle_, grid_, surface_);
  s.unconfirmed_ = unconfirmed_;
  s.use_cells_ = use_cells_;
  s.route_ = route_;
  s.embree_ = embree_;
  s.stroke_ = stroke_;
  s.budget_ = budget_;
  return s;
}

BoxScene BoxScene::without_tables() const {
  std::vector<HapticBox> frames;
  frames.reserve(boxes_.size());
  for (const HapticBox& b : boxes_) frames.push_back(b.frame());
  BoxScene s = with_boxes(std::move(frames));
  s.set_route(SceneRoute::embree);
  return s;
}

bool BoxScene::refines() const noexcept { return cells_ != nullptr || has_triangle_ids(); }

BoxScene BoxScene::without_triangle_ids() const {
  if (!cells_) return *this;
  std::vector<HapticBox> boxes;
  boxes.reserve(boxes_.size());
  for (const HapticBox& b : boxes_) boxes.push_back(b.without_refinement());
  return with_boxes(std::move(boxes));
}

void BoxScene::set_piece_of_triangle(std::vector<std::uint32_t> piece_of_triangle) {
  for (std::uint32_t id : piece_of_triangle)
    if (id >= boxes_.size())
      throw InvalidInput("box scene: piece id " + std::to_string(id) + " but " + std::to_string(boxes_.size()) +
                         " boxes");
  piece_of_triangle_ = std::move(piece_of_triangle);
}

std::size_t BoxScene::table_bytes() const {
  std::size_t sum = 0;
  for (const HapticBox& box : boxes_) sum += box.table_bytes();
  return sum;
}

std::size_t BoxScene::memory_bytes() const {
  return table_bytes() + refinement_bytes() + (surface_ ? surface_->normal_map_bytes() : 0) +
         (grid_ ? grid_->bytes() : 0) + (cells_ ? cells_->bytes() : 0) + embree_bytes();
}

std::size_t BoxScene::refinement_bytes() const {
  std::size_t sum = surface_ ? surface_->bytes() : 0;
  const SurfaceTriangles* counted = surface_.get();
  for (const HapticBox& box : boxes_) {
    sum += box.triangle_id_bytes();
    if (!surface_ && box.refines() && box.surface().get() != counted) {  // boxes on different surfaces
      counted = box.surface().get();
      sum += counted->bytes();
    }
  }
  return sum;
}

BoxScene BoxScene::compressed(const CodecOptions& options) const {
  std::vector<HapticBox> boxes;
  boxes.reserve(boxes_.size());
  for (const HapticBox& box : boxes_) boxes.push_back(box.compressed(options));
  BoxScene s(std::move(boxes), source_, piece_of_triangle_, grid_, surface_);
  s.budget_ = budget_;
  s.route_ = route_;
  s.embree_ = embree_;
  return s;
}

} // namespace hb
