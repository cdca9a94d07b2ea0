// Embree scene wrapper.
//  1. One Embree device per process (created on first use, shared by scenes); its error
//     callback stores the last error, which the wrapper turns into hb::LibraryError.
//  2. A scene holds one triangle geometry: the mesh's vertices and the selected triangles;
//     a primitive id maps back to the mesh's triangle id.
//  3. intersect() refuses (misses) rays outside Embree's valid range, uses rtcIntersect1 (single rays were faster than packets here) and
//     interpolates the vertex normals at the hit's barycentric coordinates.
#include "exact/embree_scene.h"
#include "errors.h"
#include <embree3/rtcore.h>
#include <algorithm>
#include <cmath>
#include <limits>
#include <mutex>
#include <string>

namespace hb {
namespace {

struct DeviceHolder {
  RTCDevice device = nullptr;
  std::mutex mutex;
  std::string last_error;
  DeviceHolder() {
    device = rtcNewDevice(nullptr);
    if (device) {
      rtcSetDeviceErrorFunction(
          device,
          [](void* user, RTCError code, const char* str) {
            auto* self = static_cast<DeviceHolder*>(user);
            std::lock_guard<std::mutex> lock(self->mutex);
            self->last_error = "Embree error " + std::to_string(int(code)) + ": " + (str ? str : "");
          },
          this);
    }
  }
  ~DeviceHolder() {
    if (device) rtcReleaseDevice(device);
  }
  void throw_if_error(const char* where) {
    std::lock_guard<std::mutex> lock(mutex);
    if (!last_error.empty()) {
      std::string e = std::string(where) + ": " + last_error;
      last_error.clear();
      throw LibraryError(e);
    }
  }
};

DeviceHolder& device_holder() {
  static DeviceHolder holder;
  if (!holder.device) throw LibraryError("Embree: could not create a device (rtcNewDevice failed)");
  return holder;
}

} // namespace

struct EmbreeScene::Impl {
  RTCScene scene = nullptr;
  std::vector<std::uint32_t> prim_to_triangle;  // empty: identity
  ~Impl() {
    if (scene) rtcReleaseScene(scene);
  }
};

EmbreeScene::EmbreeScene(const TriangleMesh& mesh, const std::vector<std::uint32_t>& triangles)
    : EmbreeScene(mesh, triangles, triangles.empty() ? BvhBuild::best : BvhBuild::quick) {}

EmbreeScene::EmbreeScene(const TriangleMesh& mesh, const std::vector<std::uint32_t>& triangles, BvhBuild build)
    : mesh_(mesh), impl_(std::make_unique<Impl>()) {
  DeviceHolder& holder = device_holder();
  RTCDevice device = holder.device;
  const std::size_t count = triangles.empty() ? mesh.triangle_count() : triangles.size();
  if (count == 0) throw InvalidInput("EmbreeScene: no triangles to build a scene from");
  if (mesh.normals.size() != mesh.positions.size())
    throw InvalidInput("EmbreeScene: mesh has no vertex normals (call compute_vertex_normals)");

  // A scene of some triangles holds only their vertices (a piece of a 13M-triangle mesh would
  // otherwise copy and check all of them, once per piece): the same positions in the same
  // triangles, so the same BVH and the same hits.
  std::vector<std::uint32_t> used;   // a subset's vertices in first-use order (empty: all)
  std::vector<std::uint32_t> local;  // mesh vertex -> index in `used`
  if (!triangles.empty()) {
    local.assign(mesh.vertex_count(), 0xffffffffu);
    for (std::uint32_t k : triangles) {
      if (k >= mesh.triangle_count())
        throw InvalidInput("EmbreeScene: triangle " + std::to_string(k) + " is beyond the mesh's " +
                           std::to_string(mesh.triangle_count()));
      for (int c = 0; c < 3; ++c) {
        const std::uint32_t v = mesh.triangles[k][c];
        if (v >= local.size())
          throw InvalidInput("EmbreeScene: triangle " + std::to_string(k) + " names vertex " + std::to_string(v) +
                             ", the mesh has " + std::to_string(local.size()));
        if (local[v] == 0xffffffffu) {
          local[v] = std::uint32_t(used.size());
          used.push_back(v);
        }
      }
    }
  }
  const std::size_t vertex_count = triangles.empty() ? mesh.vertex_count() : used.size();
  for (std::size_t i = 0; i < vertex_count; ++i) {
    const std::size_t v = used.empty() ? i : used[i];
    if (!(mesh.positions[v].cwiseAbs().maxCoeff() <= kMaxCoordinate))
      throw InvalidInput("EmbreeScene: vertex " + std::to_string(v) +
                         " is non-finite or beyond the supported range (|x| <= 1e15)");
  }
  impl_->scene = rtcNewScene(device);
  // A piece's scene, built once to cast its box's rays, takes the quick build (half the 832K
  // bake's table time; the same tables on six models, byte for byte: the same nearest hits).
  rtcSetSceneBuildQuality(impl_->scene, build == BvhBuild::best ? RTC_BUILD_QUALITY_HIGH : RTC_BUILD_QUALITY_MEDIUM);
  RTCGeometry geom = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(
      geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), vertex_count));
  auto* indices = static_cast<std::uint32_t*>(rtcSetNewGeometryBuffer(
      geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(std::uint32_t), count));
  holder.throw_if_error("EmbreeScene: allocating buffers");
  for (std::size_t i = 0; i < vertex_count; ++i)
    for (int c = 0; c < 3; ++c) vertices[3 * i + c] = mesh.positions[used.empty() ? i : used[i]][c];
  for (std::size_t k = 0; k < count; ++k) {
    const Triangle& t = mesh.triangles[triangles.empty() ? k : triangles[k]];
    for (int c = 0; c < 3; ++c) indices[3 * k + c] = local.empty() ? t[c] : local[t[c]];
  }
  if (!triangles.empty()) impl_->prim_to_triangle = triangles;
  rtcCommitGeometry(geom);
  rtcAttachGeometry(impl_->scene, geom);
  rtcReleaseGeometry(geom);
  rtcCommitScene(impl_->scene);
  holder.throw_if_error("EmbreeScene: building the BVH");
}

EmbreeScene::~EmbreeScene() = default;

namespace {

// Embree asserts (aborts the process) on a ray outside its valid range: such a ray, which
// no mesh within kMaxCoordinate can need, misses.
bool valid_ray(const Vec3& origin, const Vec3& dir, float t_near, float t_far) noexcept {
  constexpr float kLarge = 1e18f;
  return origin.cwiseAbs().maxCoeff() <= kLarge && dir.cwiseAbs().maxCoeff() <= kLarge && t_near >= 0.f &&
         t_near <= t_far && !std::isnan(t_far);
}

void set_ray(RTCRayHit& rh, const Vec3& origin, const Vec3& dir, float t_near, float t_far) noexcept {
  rh.ray.org_x = origin.x();
  rh.ray.org_y = origin.y();
  rh.ray.org_z = origin.z();
  rh.ray.dir_x = dir.x();
  rh.ray.dir_y = dir.y();
  rh.ray.dir_z = dir.z();
  rh.ray.tnear = t_near;
  rh.ray.tfar = t_far;
  rh.ray.mask = 0xffffffffu;
  rh.ray.flags = 0;
  rh.ray.time = 0.f;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
}

// The hit of `rh` (a ray along unit `dir`) with its shaded and geometric normals.
RayHit to_ray_hit(const RTCRayHit& rh, const Vec3& dir, const TriangleMesh& mesh,
                  const std::vector<std::uint32_t>& prim_to_triangle) noexcept {
  RayHit out;
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return out;
  out.hit = true;
  out.t = rh.ray.tfar;
  out.triangle = prim_to_triangle.empty() ? rh.hit.primID : prim_to_triangle[rh.hit.primID];
  const Triangle& tri = mesh.triangles[out.triangle];
  const Vec3& a = mesh.positions[tri[0]];
  const Vec3 geometric = (mesh.positions[tri[1]] - a).cross(mesh.positions[tri[2]] - a);
  const float u = rh.hit.u, v = rh.hit.v;
  Vec3 shaded = (1.f - u - v) * mesh.normals[tri[0]] + u * mesh.normals[tri[1]] + v * mesh.normals[tri[2]];
  if (shaded.dot(geometric) < 0.f || shaded.squaredNorm() < 1e-12f) shaded = geometric;
  const float len = shaded.norm();
  out.normal = len > 0.f ? Vec3(shaded / len) : Vec3(-dir);
  out.back_face = geometric.dot(dir) > 0.f;
  const float glen = geometric.norm();
  if (glen > 0.f && glen <= std::numeric_limits<float>::max()) out.face_normal = geometric / glen;
  return out;
}

// The point of triangle abc nearest p (Ericson, Real-Time Collision Detection 5.1.5).
Vec3 closest_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) noexcept {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const float d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0.f && d2 <= 0.f) return a;
  const Vec3 bp = p - b;
  const float d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0.f && d4 <= d3) return b;
  const float vc = d1 * d4 - d3 * d2;
  if (vc <= 0.f && d1 >= 0.f && d3 <= 0.f) return a + ab * (d1 / (d1 - d3));
  const Vec3 cp = p - c;
  const float d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0.f && d5 <= d6) return c;
  const float vb = d5 * d2 - d1 * d6;
  if (vb <= 0.f && d2 >= 0.f && d6 <= 0.f) return a + ac * (d2 / (d2 - d6));
  const float va = d3 * d6 - d5 * d4;
  if (va <= 0.f && (d4 - d3) >= 0.f && (d5 - d6) >= 0.f) return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
  const float denom = 1.f / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

struct ReachQuery {
  const TriangleMesh* mesh;
  const std::vector<std::uint32_t>* prim_to_triangle;
  Vec3 centre;
  bool found = false;
};

} // namespace

RayHit EmbreeScene::intersect(const Vec3& origin, const Vec3& dir, float t_near,
                              float t_far) const noexcept {
  if (!valid_ray(origin, dir, t_near, t_far)) return RayHit{};
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rh;
  set_ray(rh, origin, dir, t_near, t_far);
  rtcIntersect1(impl_->scene, &context, &rh);
  return to_ray_hit(rh, dir, mesh_, impl_->prim_to_triangle);
}

void EmbreeScene::intersect_many(const Vec3* origins, const Vec3* dirs, const float* t_far, std::size_t count,
                                 RayHit* out) const noexcept {
  constexpr std::size_t kChunk = 64;
  RTCRayHit rays[kChunk];
  std::uint32_t index[kChunk];
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
  for (std::size_t first = 0; first < count; first += kChunk) {
    const std::size_t last = std::min(count, first + kChunk);
    std::size_t m = 0;
    for (std::size_t i = first; i < last; ++i) {
      out[i] = RayHit{};
      if (!valid_ray(origins[i], dirs[i], 0.f, t_far[i])) continue;
      set_ray(rays[m], origins[i], dirs[i], 0.f, t_far[i]);
      index[m++] = std::uint32_t(i);
    }
    if (m == 0) continue;
    rtcIntersect1M(impl_->scene, &context, rays, unsigned(m), sizeof(RTCRayHit));
    for (std::size_t j = 0; j < m; ++j) out[index[j]] = to_ray_hit(rays[j], dirs[index[j]], mesh_, impl_->prim_to_triangle);
  }
}

bool EmbreeScene::any_within(const Vec3& centre, float radius) const noexcept {
  if (!(centre.cwiseAbs().maxCoeff() <= 1e18f) || !(radius >= 0.f) || !(radius <= 1e18f)) return true;
  RTCPointQuery query;
  query.x = centre.x();
  query.y = centre.y();
  query.z = centre.z();
  query.time = 0.f;
  query.radius = radius;
  RTCPointQueryContext context;
  rtcInitPointQueryContext(&context);
  ReachQuery reach{&mesh_, &impl_->prim_to_triangle, centre};
  rtcPointQuery(impl_->scene, &query, &context,
                [](RTCPointQueryFunctionArguments* args) -> bool {
                  auto* r = static_cast<ReachQuery*>(args->userPtr);
                  const std::uint32_t k = r->prim_to_triangle->empty() ? args->primID : (*r->prim_to_triangle)[args->primID];
                  const Triangle& tri = r->mesh->triangles[k];
                  const Vec3 q = closest_on_triangle(r->centre, r->mesh->positions[tri[0]], r->mesh->positions[tri[1]],
                                                     r->mesh->positions[tri[2]]);
                  if ((q - r->centre).norm() > args->query->radius) return false;
                  r->found = true;
                  args->query->radius = 0.f;  // nothing is nearer than 0: the traversal ends
                  return true;
                },
                &reach);
  return reach.found;
}

} // namespace hb
