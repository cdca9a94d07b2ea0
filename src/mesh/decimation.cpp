// Mesh simplification within a deviation bound (decimation.h).
//  1. Small meshes (<= chunk_triangles): one OpenMesh TriMesh of all faces; faces it refuses
//     (complex edges or vertices) are kept as they are and their vertices locked, as are
//     boundary vertices; ModQuadricT (max error bound^2: the quadric is the sum of squared
//     distances to the merged face planes, so each is within the bound) as priority and
//     ModNormalFlippingT; greedy sweeps (SweepDecimater) at half the bound, then
//     DecimaterT's heap at the other half on what is left, collapsing while any is legal.
//  2. Large meshes: triangles sorted by the Morton code of their centroid and cut into chunks
//     of about chunk_triangles; a vertex used by two chunks is locked in both. The chunks are
//     swept in parallel (TBB; each chunk is its own OpenMesh mesh) at half the bound, the
//     surviving faces joined (halfedge collapses keep original vertices, so the chunks agree
//     at their shared vertices), then the joined mesh is decimated once at the other half,
//     which removes the chunk borders' extra vertices.
//     A vertex whose one-ring's shaded normals (the full mesh's vertex normals) differ
//     from its own by more than max_shading_deviation_deg stays (ModShadingT): the exact
//     answer shades with those normals, and faces across such a vertex would not.
//  3. The kept vertices are original vertices: they keep the full mesh's vertex normals
//     (the shading the full mesh has there), or get recomputed ones when it has none.
#include <OpenMesh/Core/IO/MeshIO.hh>  // must precede the mesh kernel headers
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Tools/Decimater/DecimaterT.hh>
#include <OpenMesh/Tools/Decimater/ModNormalFlippingT.hh>
#include <OpenMesh/Tools/Decimater/ModQuadricT.hh>

#include "errors.h"
#include "mesh/decimation.h"
#include "mesh/openmesh_support.h"

#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>
#include <algorithm>
#include <chrono>
#include <cfloat>
#include <cmath>

namespace hb {
namespace {

using OmMesh = OpenMesh::TriMesh_ArrayKernelT<>;

// A binary module: a vertex may be removed only when the full mesh's shaded normals of its
// one-ring are within `cos_max` of its own, so the normals interpolated across the faces
// that replace it stay close to the shading the full mesh has there (the exact answer's
// normals are the full mesh's vertex normals interpolated).
template <class MeshT>
class ModShadingT : public OpenMesh::Decimater::ModBaseT<MeshT> {
public:
  DECIMATING_MODULE(ModShadingT, MeshT, Shading);
  explicit ModShadingT(MeshT& mesh) : Base(mesh, true) {}
  void set(const std::vector<Vec3>* normals, double max_deg) {
    normals_ = normals;
    cos_max_ = float(std::cos(max_deg * M_PI / 180.0));
  }
  float collapse_priority(const CollapseInfo& ci) override {
    if (!normals_) return float(Base::LEGAL_COLLAPSE);
    const Vec3& n0 = (*normals_)[std::size_t(ci.v0.idx())];
    for (auto v : Base::mesh().vv_range(ci.v0))
      if (n0.dot((*normals_)[std::size_t(v.idx())]) < cos_max_) return float(Base::ILLEGAL_COLLAPSE);
    return float(Base::LEGAL_COLLAPSE);
  }

private:
  const std::vector<Vec3>* normals_ = nullptr;
  float cos_max_ = -1.f;
};

// Greedy sweeps (no heap): vertices in a seeded random order, each collapsed along the
// cheapest legal of its outgoing halfedges, the modules' bounds enforced as in DecimaterT;
// sweeps repeat until one removes fewer than 2% of the vertices left. About one priority
// evaluation per outgoing halfedge per collapse, where DecimaterT re-evaluates the whole
// one-ring after each collapse (measured on the 832K armadillo: most of its time). The
// heap pass that follows orders what is left.
class SweepDecimater : public OpenMesh::Decimater::BaseDecimaterT<OmMesh> {
public:
  explicit SweepDecimater(OmMesh& mesh) : BaseDecimaterT<OmMesh>(mesh), mesh_(mesh) {}
  std::size_t sweep(std::uint64_t seed) {
    using CollapseInfo = OpenMesh::Decimater::CollapseInfoT<OmMesh>;
    std::vector<int> order(mesh_.n_vertices());
    for (std::size_t k = 0; k < order.size(); ++k) order[k] = int(k);
    std::uint64_t state = seed * 0x9E3779B97F4A7C15ull + 1;
    for (std::size_t k = order.size(); k > 1; --k) {  // Fisher-Yates, splitmix-like steps
      state ^= state >> 33, state *= 0xff51afd7ed558ccdull, state ^= state >> 33;
      std::swap(order[k - 1], order[std::size_t(state % k)]);
    }
    std::size_t total = 0, alive = order.size();
    for (int round = 0; round < 16; ++round) {
      std::size_t done = 0;
      for (int idx : order) {
        const OmMesh::VertexHandle v(idx);
        if (mesh_.status(v).deleted() || mesh_.status(v).locked()) continue;
        OmMesh::HalfedgeHandle best;
        float best_energy = FLT_MAX;
        for (auto h : mesh_.voh_range(v)) {
          CollapseInfo ci(mesh_, h);
          if (!is_collapse_legal(ci)) continue;
          const float e = collapse_priority(ci);
          if (e != float(OpenMesh::Decimater::ModBaseT<OmMesh>::ILLEGAL_COLLAPSE) && e < best_energy)
            best_energy = e, best = h;
        }
        if (!best.is_valid()) continue;
        CollapseInfo ci(mesh_, best);
        preprocess_collapse(ci);
        mesh_.collapse(best);
        for (auto f : mesh_.vf_range(ci.v1))
          if (!mesh_.status(f).deleted()) mesh_.set_normal(f, mesh_.calc_face_normal(f));
        postprocess_collapse(ci);
        ++done;
      }
      total += done;
      alive -= done;
      if (done < alive / 50 + 1) break;
    }
    return total;
  }

private:
  OmMesh& mesh_;
};

// The three modules every pass uses: the quadric bound (squared: OpenMesh's quadric error is a
// squared distance), no normal flip beyond `normal_deg`, and the shading check.
struct DecimationModules {
  OpenMesh::Decimater::ModQuadricT<OmMesh>::Handle quadric;
  OpenMesh::Decimater::ModNormalFlippingT<OmMesh>::Handle flipping;
  ModShadingT<OmMesh>::Handle shading;

  template <class Decimater>
  void attach(Decimater& d, const std::vector<Vec3>& normals, double bound, double normal_deg, double shading_deg) {
    d.add(quadric);
    d.add(flipping);
    d.add(shading);
    d.module(shading).set(normals.empty() ? nullptr : &normals, shading_deg);
    d.module(quadric).set_max_err(bound * bound, false);
    d.module(flipping).set_max_normal_deviation(normal_deg);
    if (!d.initialize()) throw LibraryError("decimate: OpenMesh's decimater did not initialize");
  }
};

// Decimates the faces `faces` (vertex ids into mesh.positions) with the vertices `locked`
// (sorted) kept; returns the surviving faces (same vertex ids) in `out`, and counts the faces
// OpenMesh refused (kept unchanged in `out`).
void decimate_faces(const TriangleMesh& mesh, const std::vector<Triangle>& faces, const std::vector<std::uint32_t>& locked,
                    double bound, double normal_deg, double shading_deg, bool greedy, std::uint64_t seed, std::vector<Triangle>& out,
                    std::size_t& refused) {
  // Local vertex ids: the sorted distinct vertices of the faces.
  std::vector<std::uint32_t> verts;
  verts.reserve(faces.size() * 3 / 2 + 8);
  for (const Triangle& t : faces) verts.insert(verts.end(), t.begin(), t.end());
  std::sort(verts.begin(), verts.end());
  verts.erase(std::unique(verts.begin(), verts.end()), verts.end());
  const auto local = [&](std::uint32_t v) {
    return OmMesh::VertexHandle(int(std::lower_bound(verts.begin(), verts.end(), v) - verts.begin()));
  };
  OmMesh om;
  om.request_vertex_status();
  om.request_edge_status();
  om.request_face_status();
  om.request_face_normals();
  om.reserve(verts.size(), faces.size() * 3 / 2 + 8, faces.size());
  for (std::uint32_t v : verts) {
    const Vec3& p = mesh.positions[v];
    om.add_vertex(OmMesh::Point(p.x(), p.y(), p.z()));
  }
  // The full mesh's shaded normals, by local vertex (ModShadingT).
  std::vector<Vec3> normals;
  if (shading_deg < 180.0 && mesh.normals.size() == mesh.positions.size()) {
    normals.reserve(verts.size());
    for (std::uint32_t v : verts) normals.push_back(mesh.normals[v]);
  }
  std::vector<bool> lock(verts.size(), false);
  for (std::uint32_t v : locked)
    if (std::binary_search(verts.begin(), verts.end(), v)) lock[std::size_t(local(v).idx())] = true;
  for (const Triangle& t : faces) {
    const auto a = local(t[0]), b = local(t[1]), c = local(t[2]);
    if (a == b || b == c || a == c || !om.add_face(a, b, c).is_valid()) {
      out.push_back(t);  // refused: kept as it is, its vertices locked
      ++refused;
      lock[std::size_t(a.idx())] = lock[std::size_t(b.idx())] = lock[std::size_t(c.idx())] = true;
    }
  }
  for (const auto vh : om.vertices())
    if (lock[std::size_t(vh.idx())] || om.is_boundary(vh)) om.status(vh).set_locked(true);
  om.update_face_normals();
  if (bound > 0.0 && greedy) {
    SweepDecimater sweeper(om);
    DecimationModules modules;
    modules.attach(sweeper, normals, bound, normal_deg, shading_deg);
    sweeper.sweep(seed);
  } else if (bound > 0.0) {
    OpenMesh::Decimater::DecimaterT<OmMesh> decimater(om);
    DecimationModules modules;
    modules.attach(decimater, normals, bound, normal_deg, shading_deg);
    decimater.decimate(0);
  }
  for (const auto fh : om.faces()) {
    if (om.status(fh).deleted()) continue;
    auto fv = om.fv_iter(fh);
    Triangle t;
    for (int k = 0; k < 3; ++k, ++fv) t[std::size_t(k)] = verts[std::size_t(fv->idx())];
    out.push_back(t);
  }
}

std::uint32_t spread_bits(std::uint32_t x) {  // 10 bits to every third of 30
  x &= 0x3ff;
  x = (x | (x << 16)) & 0x030000ff;
  x = (x | (x << 8)) & 0x0300f00f;
  x = (x | (x << 4)) & 0x030c30c3;
  x = (x | (x << 2)) & 0x09249249;
  return x;
}

} // namespace

DecimationResult decimate(const TriangleMesh& mesh, const DecimationOptions& options) {
  if (mesh.triangle_count() == 0) throw InvalidInput("decimate: the mesh has no triangles");
  if (!(options.max_deviation >= 0.0) || !std::isfinite(options.max_deviation))
    throw InvalidInput("decimate: max deviation must be finite and >= 0, got " + std::to_string(options.max_deviation));
  const auto t0 = std::chrono::steady_clock::now();
  DecimationResult result;
  std::vector<Triangle> kept;
  // OpenMesh's log streams are process-global; its stream buffers serialise writes, so the
  // chunks may run at once while this thread holds the capture.
  std::lock_guard<std::mutex> lock(detail::openmesh_mutex());
  detail::OpenMeshChatterCapture chatter;
  const std::size_t n = mesh.triangle_count();
  const double normal_deg = options.max_normal_deviation_deg, shading_deg = options.max_shading_deviation_deg;
  if (options.chunk_triangles == 0 || n <= options.chunk_triangles) {
    // Greedy sweeps first (their own half of the bound), then the heap at the other half.
    std::vector<Triangle> swept;
    std::size_t refused = 0;
    decimate_faces(mesh, mesh.triangles, {}, 0.5 * options.max_deviation, normal_deg, shading_deg, true, 1, swept, refused);
    decimate_faces(mesh, swept, {}, 0.5 * options.max_deviation, normal_deg, shading_deg, false, 0, kept, result.unmanifold_kept);
  } else {
    // Morton order of the centroids, cut into chunks.
    const Bounds b = mesh.bounds();
    const Vec3 lo = b.min, extent = (b.max - b.min).cwiseMax(Vec3::Constant(1e-30f));
    std::vector<std::uint64_t> keyed(n);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1 << 14), [&](const auto& r) {
      for (std::size_t t = r.begin(); t != r.end(); ++t) {
        const Triangle& tri = mesh.triangles[t];
        const Vec3 c = (mesh.positions[tri[0]] + mesh.positions[tri[1]] + mesh.positions[tri[2]]) / 3.f;
        std::uint32_t code = 0;
        for (int k = 0; k < 3; ++k) {
          const float f = std::min(1.f, std::max(0.f, (c[k] - lo[k]) / extent[k]));
          code |= spread_bits(std::uint32_t(f * 1023.f)) << k;
        }
        keyed[t] = (std::uint64_t(code) << 32) | std::uint64_t(t);
      }
    });
    tbb::parallel_sort(keyed.begin(), keyed.end());
    const std::size_t chunks = (n + options.chunk_triangles - 1) / options.chunk_triangles;
    result.chunks = chunks;
    const auto chunk_of = [&](std::size_t rank) { return std::uint32_t(rank * chunks / n); };
    // Vertices used by two chunks are locked in both.
    constexpr std::uint32_t kUnseen = 0xffffffffu, kShared = 0xfffffffeu;
    std::vector<std::uint32_t> owner(mesh.vertex_count(), kUnseen);
    for (std::size_t r = 0; r < n; ++r) {
      const std::uint32_t c = chunk_of(r);
      for (std::uint32_t v : mesh.triangles[std::uint32_t(keyed[r])])
        owner[v] = owner[v] == kUnseen ? c : owner[v] == c ? c : kShared;
    }
    std::vector<std::uint32_t> shared;
    for (std::uint32_t v = 0; v < owner.size(); ++v)
      if (owner[v] == kShared) shared.push_back(v);
    std::vector<std::vector<Triangle>> outs(chunks);
    std::vector<std::size_t> refused(chunks, 0);
    tbb::parallel_for(std::size_t(0), chunks, [&](std::size_t c) {
      const std::size_t first = (c * n + chunks - 1) / chunks, last = ((c + 1) * n + chunks - 1) / chunks;
      std::vector<Triangle> faces;
      faces.reserve(last - first);
      for (std::size_t r = first; r < last; ++r) faces.push_back(mesh.triangles[std::uint32_t(keyed[r])]);
      std::vector<std::uint32_t> locked;
      for (const Triangle& t : faces)
        for (std::uint32_t v : t)
          if (owner[v] == kShared) locked.push_back(v);
      std::sort(locked.begin(), locked.end());
      locked.erase(std::unique(locked.begin(), locked.end()), locked.end());
      decimate_faces(mesh, faces, locked, 0.5 * options.max_deviation, normal_deg, shading_deg, true, c + 1, outs[c], refused[c]);
    });
    std::vector<Triangle> joined;
    for (auto& o : outs) joined.insert(joined.end(), o.begin(), o.end());
    std::size_t refused_again = 0;
    decimate_faces(mesh, joined, {}, 0.5 * options.max_deviation, normal_deg, shading_deg, false, 0, kept, refused_again);
    result.unmanifold_kept = refused_again;  // what the last pass could not take
  }
  // Compact the kept vertices.
  constexpr std::uint32_t kNone = 0xffffffffu;
  std::vector<std::uint32_t> remap(mesh.vertex_count(), kNone);
  const bool has_normals = mesh.normals.size() == mesh.positions.size();
  TriangleMesh& out = result.mesh;
  out.triangles.reserve(kept.size());
  for (Triangle t : kept) {
    for (std::uint32_t& v : t) {
      if (remap[v] == kNone) {
        remap[v] = std::uint32_t(out.positions.size());
        out.positions.push_back(mesh.positions[v]);
        if (has_normals) out.normals.push_back(mesh.normals[v]);
      }
      v = remap[v];
    }
    out.triangles.push_back(t);
  }
  if (!has_normals) out.compute_vertex_normals();
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return result;
}

} // namespace hb
