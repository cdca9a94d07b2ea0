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

RayHit EmbreeScene::intersect(const Vec3& origin, const Vec3& dir, float t_near,
                              float t_far) const noexcept {
  // Embree asserts (aborts the process) on a ray outside its valid range: such a ray, which
  // no mesh within kMaxCoordinate can need, misses.
  constexpr float kLarge = 1e18f;
  if (!(origin.cwiseAbs().maxCoeff() <= kLarge && dir.cwiseAbs().maxCoeff() <= kLarge && t_near >= 0.f &&
        t_near <= t_far && !std::isnan(t_far)))
    return RayHit{};
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rh;
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
  rtcIntersect1(impl_->scene, &context, &rh);

  RayHit out;
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return out;
  out.hit = true;
  out.t = rh.ray.tfar;
  out.triangle = impl_->prim_to_triangle.empty() ? rh.hit.primID : impl_->prim_to_triangle[rh.hit.primID];
  const Triangle& tri = mesh_.triangles[out.triangle];
  const Vec3& a = mesh_.positions[tri[0]];
  const Vec3 geometric = (mesh_.positions[tri[1]] - a).cross(mesh_.positions[tri[2]] - a);
  const float u = rh.hit.u, v = rh.hit.v;
  Vec3 shaded = (1.f - u - v) * mesh_.normals[tri[0]] + u * mesh_.normals[tri[1]] + v * mesh_.normals[tri[2]];
  if (shaded.dot(geometric) < 0.f || shaded.squaredNorm() < 1e-12f) shaded = geometric;
  const float len = shaded.norm();
  out.normal = len > 0.f ? Vec3(shaded / len) : Vec3(-dir);
  out.back_face = geometric.dot(dir) > 0.f;
  const float glen = geometric.norm();
  if (glen > 0.f && glen <= std::numeric_limits<float>::max()) out.face_normal = geometric / glen;
  return out;
}

} // namespace hb
