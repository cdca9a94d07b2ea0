#include "decomposition/plane_split.h"
#include "errors.h"
#include <cmath>
#include <map>
#include <unordered_map>

namespace hb {

std::size_t compact_piece_ids(std::vector<std::uint32_t>& ids) {
  std::unordered_map<std::uint32_t, std::uint32_t> remap;
  for (auto& id : ids) {
    auto it = remap.emplace(id, std::uint32_t(remap.size())).first;
    id = it->second;
  }
  return remap.size();
}

std::vector<std::uint32_t> split_by_planes(const TriangleMesh& mesh, const std::vector<CutPlane>& planes,
                                           const std::vector<std::uint32_t>& base) {
  const std::size_t count = mesh.triangle_count();
  if (!base.empty() && base.size() != count)
    throw InvalidInput("split_by_planes: base has " + std::to_string(base.size()) + " ids, the mesh has " +
                       std::to_string(count) + " triangles");
  for (const CutPlane& p : planes)
    if (!(p.normal.squaredNorm() > 0.f) || !p.normal.allFinite() || !p.point.allFinite())
      throw InvalidInput("split_by_planes: plane with a zero or non-finite normal or point");
  std::map<std::vector<std::uint8_t>, std::uint32_t> key_to_id;
  std::vector<std::uint32_t> out(count);
  std::vector<std::uint8_t> key(planes.size() + 4);
  for (std::uint32_t t = 0; t < count; ++t) {
    const Triangle& tri = mesh.triangles[t];
    const Vec3 c = (mesh.positions[tri[0]] + mesh.positions[tri[1]] + mesh.positions[tri[2]]) / 3.f;
    const std::uint32_t b = base.empty() ? 0u : base[t];
    for (int k = 0; k < 4; ++k) key[k] = std::uint8_t(b >> (8 * k));
    for (std::size_t k = 0; k < planes.size(); ++k)
      key[4 + k] = (c - planes[k].point).dot(planes[k].normal) >= 0.f ? 1 : 0;
    out[t] = key_to_id.emplace(key, std::uint32_t(key_to_id.size())).first->second;
  }
  return out;
}

} // namespace hb
