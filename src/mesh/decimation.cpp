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
#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <chrono>
#include <mutex>
#include <type_traits>
#include <cfloat>
#include <cmath>

namespace hb {
namespace {

using OmMesh = OpenMesh::TriMesh_ArrayKernelT<>;

// Per face: the original vertices (global ids) removed into it (ShadingCheck::fit).
using FacePoints = std::vector<std::uint32_t>;

// A binary module for the shading (DecimationOptions::ShadingCheck).
//  ring: a vertex may be removed only when the full mesh's shaded normals of its one-ring
//    are within `cos_max` of its own, so the normals interpolated across the faces that
//    replace it stay close to the shading the full mesh has there.
//  fit: every face carries the removed vertices it covers; a collapse moves those of the
//    faces around v0 (and v0) to the nearest of the faces that v0's become, and is legal
//    when each of these faces can fit corner normals of its own to the vertices' shaded
//    normals (and its corners') within the bound: what hb::fit_shading does afterwards.
template <class MeshT>
class ModShadingT : public OpenMesh::Decimater::ModBaseT<MeshT> {
public:
  DECIMATING_MODULE(ModShadingT, MeshT, Shading);
  explicit ModShadingT(MeshT& mesh) : Base(mesh, true) {}
  ~ModShadingT() override {
    if (points_.is_valid()) Base::mesh().remove_property(points_);
  }
  void set(const std::vector<Vec3>* normals, double max_deg) {
    normals_ = normals;
    cos_max_ = float(std::cos(max_deg * M_PI / 180.0));
  }
  // Fit mode: local vertex v is global vertex verts[v] of `full` (whose normals are used);
  // the face property receives the carried vertices.
  void set_fit(const TriangleMesh* full, const std::vector<std::uint32_t>* verts) {
    full_ = full;
    verts_ = verts;
    Base::mesh().add_property(points_);
  }
  FacePoints& points(typename MeshT::FaceHandle f) { return Base::mesh().property(points_, f); }

  float collapse_priority(const CollapseInfo& ci) override {
    if (full_) return fit_priority(ci);
    if (!normals_) return float(Base::LEGAL_COLLAPSE);
    const Vec3& n0 = (*normals_)[std::size_t(ci.v0.idx())];
    for (auto v : Base::mesh().vv_range(ci.v0))
      if (n0.dot((*normals_)[std::size_t(v.idx())]) < cos_max_) return float(Base::ILLEGAL_COLLAPSE);
    return float(Base::LEGAL_COLLAPSE);
  }
  void preprocess_collapse(const CollapseInfo& ci) override {
    if (!full_) return;
    gather(ci);
    for (auto f : Base::mesh().vf_range(ci.v0)) points(f).clear();
  }
  void postprocess_collapse(const CollapseInfo& ci) override {
    if (!full_) return;
    // The faces gathered in preprocess_collapse now have v1 where they had v0.
    distribute(ci.v0, ci.v1);
    for (std::size_t k = 0; k < faces_.size(); ++k) {
      FacePoints& p = points(faces_[k]);
      p.insert(p.end(), assigned_[k].begin(), assigned_[k].end());
    }
  }

private:
  // The faces v0's become (all but fl and fr) and every carried vertex around v0, v0 too.
  void gather(const CollapseInfo& ci) {
    faces_.clear();
    pool_.clear();
    for (auto f : Base::mesh().vf_range(ci.v0)) {
      if (f != ci.fl && f != ci.fr) faces_.push_back(f);
      const FacePoints& p = points(f);
      pool_.insert(pool_.end(), p.begin(), p.end());
    }
    pool_.push_back((*verts_)[std::size_t(ci.v0.idx())]);
  }
  // The global corner ids of face f with v0 standing for v1.
  void corners(typename MeshT::FaceHandle f, typename MeshT::VertexHandle v0, typename MeshT::VertexHandle v1,
               std::uint32_t out[3]) {
    int k = 0;
    for (auto v : Base::mesh().fv_range(f)) out[k++] = (*verts_)[std::size_t((v == v0 ? v1 : v).idx())];
  }
  // Barycentrics (clamped to the triangle, renormalised) of q's projection on triangle abc,
  // and its squared distance to the plane plus the clamping's.
  static float locate(const Vec3& q, const Vec3& a, const Vec3& b, const Vec3& c, float w[3]) {
    const Vec3 e1 = b - a, e2 = c - a, d = q - a;
    const float d11 = e1.dot(e1), d12 = e1.dot(e2), d22 = e2.dot(e2), d1 = d.dot(e1), d2 = d.dot(e2);
    const float den = d11 * d22 - d12 * d12;
    if (!(den > 0.f)) {
      w[0] = w[1] = w[2] = 1.f / 3.f;
      return (q - (a + b + c) / 3.f).squaredNorm();
    }
    float u = (d22 * d1 - d12 * d2) / den, v = (d11 * d2 - d12 * d1) / den;
    float w0 = 1.f - u - v;
    w0 = std::max(0.f, w0), u = std::max(0.f, u), v = std::max(0.f, v);
    const float sum = w0 + u + v;
    w[0] = w0 / sum, w[1] = u / sum, w[2] = v / sum;
    return (q - (w[0] * a + w[1] * b + w[2] * c)).squaredNorm();
  }
  // Each pooled vertex to the nearest of faces_ (v0 standing for v1): assigned_[k].
  void distribute(typename MeshT::VertexHandle v0, typename MeshT::VertexHandle v1) {
    assigned_.assign(faces_.size(), {});
    corner_ids_.resize(faces_.size());
    for (std::size_t k = 0; k < faces_.size(); ++k) corners(faces_[k], v0, v1, corner_ids_[k].data());
    for (std::uint32_t g : pool_) {
      const Vec3& q = full_->positions[g];
      float best = FLT_MAX, w[3];
      std::size_t at = 0;
      for (std::size_t k = 0; k < faces_.size(); ++k) {
        const auto& c = corner_ids_[k];
        const float e = locate(q, full_->positions[c[0]], full_->positions[c[1]], full_->positions[c[2]], w);
        if (e < best) best = e, at = k;
      }
      if (!faces_.empty()) assigned_[at].push_back(g);
    }
  }
  float fit_priority(const CollapseInfo& ci) {
    gather(ci);
    distribute(ci.v0, ci.v1);
    for (std::size_t k = 0; k < faces_.size(); ++k)
      if (!fits(corner_ids_[k].data(), assigned_[k])) return float(Base::ILLEGAL_COLLAPSE);
    return float(Base::LEGAL_COLLAPSE);
  }
  // Whether corner normals of the triangle's own fit the shaded normals of its corners and
  // of `inside` (least squares) within the bound.
  bool fits(const std::uint32_t c[3], const FacePoints& inside) {
    const Vec3 &a = full_->positions[c[0]], &b = full_->positions[c[1]], &d = full_->positions[c[2]];
    if (inside.empty()) return true;  // the corners alone: their own normals fit exactly
    Eigen::Matrix3f m = Eigen::Matrix3f::Identity();  // the corners, weight 1 each
    Eigen::Matrix3f rhs;
    for (int k = 0; k < 3; ++k) rhs.row(k) = full_->normals[c[k]].transpose();
    float w[3];
    weights_.clear();
    for (std::uint32_t g : inside) {
      locate(full_->positions[g], a, b, d, w);
      const Eigen::Vector3f wv(w[0], w[1], w[2]);
      m += wv * wv.transpose();
      rhs += wv * full_->normals[g].transpose();
      weights_.push_back(wv);
    }
    m.diagonal().array() += 1e-4f;
    const Eigen::Matrix3f x = m.ldlt().solve(rhs);
    const auto within = [&](const Eigen::Vector3f& wv, const Vec3& target) {
      const Vec3 s = (wv.transpose() * x).transpose();
      const float len = s.norm();
      return len > 0.f && s.dot(target) >= cos_max_ * len;
    };
    for (int k = 0; k < 3; ++k)
      if (!within(Eigen::Vector3f::Unit(k), full_->normals[c[k]])) return false;
    for (std::size_t i = 0; i < inside.size(); ++i)
      if (!within(weights_[i], full_->normals[inside[i]])) return false;
    return true;
  }

  const std::vector<Vec3>* normals_ = nullptr;
  float cos_max_ = -1.f;
  const TriangleMesh* full_ = nullptr;
  const std::vector<std::uint32_t>* verts_ = nullptr;
  OpenMesh::FPropHandleT<FacePoints> points_;
  std::vector<typename MeshT::FaceHandle> faces_;
  FacePoints pool_;
  std::vector<FacePoints> assigned_;
  std::vector<std::array<std::uint32_t, 3>> corner_ids_;
  std::vector<Eigen::Vector3f> weights_;
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
        // The cheapest legal halfedge: the priorities first (the quadric and the normal
        // flips, a few dozen flops each), then the topological test (OpenMesh's
        // is_collapse_ok, a walk of both one-rings: most of the sweep's time when it ran for
        // every halfedge) in rising priority until one passes. The same halfedge as testing
        // every one (ties keep the first in the one-ring's order), so the same mesh.
        ranked_.clear();
        around_.clear();
        for (auto h : mesh_.voh_range(v)) {
          CollapseInfo ci(mesh_, h);
          const float e = collapse_priority(ci);
          ranked_.emplace_back(std::isnan(e) ? kIllegal : e, int(around_.size()));
          around_.push_back(h);
        }
        std::sort(ranked_.begin(), ranked_.end());
        OmMesh::HalfedgeHandle best;
        for (const auto& [e, k] : ranked_) {
          if (e == kIllegal || !(e < FLT_MAX)) continue;
          CollapseInfo ci(mesh_, around_[std::size_t(k)]);
          if (is_collapse_legal(ci)) {
            best = around_[std::size_t(k)];
            break;
          }
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
  static constexpr float kIllegal = float(OpenMesh::Decimater::ModBaseT<OmMesh>::ILLEGAL_COLLAPSE);
  OmMesh& mesh_;
  std::vector<std::pair<float, int>> ranked_;  // one vertex's outgoing halfedges: (priority, index into around_)
  std::vector<OmMesh::HalfedgeHandle> around_;
};

// What one pass does: the quadric bound (squared: OpenMesh's quadric error is a squared
// distance), no normal flip beyond `normal_deg`, the shading check, greedy sweeps or the heap.
struct PassSettings {
  double bound = 0.0, normal_deg = 20.0, shading_deg = 180.0;
  bool fit = false;  // ShadingCheck::fit
  bool greedy = false;
  std::uint64_t seed = 0;
};

// Faces with the removed vertices each covers (fit check only; else `points` is empty).
struct FaceSet {
  std::vector<Triangle> tris;
  std::vector<FacePoints> points;
  void push(const Triangle& t, FacePoints p) {
    tris.push_back(t);
    points.push_back(std::move(p));
  }
  void append(FaceSet&& o) {
    tris.insert(tris.end(), o.tris.begin(), o.tris.end());
    for (FacePoints& p : o.points) points.push_back(std::move(p));
  }
};

// The three modules every pass uses (handles; the decimater owns the modules).
struct DecimationModules {
  OpenMesh::Decimater::ModQuadricT<OmMesh>::Handle quadric;
  OpenMesh::Decimater::ModNormalFlippingT<OmMesh>::Handle flipping;
  ModShadingT<OmMesh>::Handle shading;
};

template <class Decimater>
void attach_modules(Decimater& d, DecimationModules& h, const TriangleMesh& mesh, const std::vector<std::uint32_t>& verts,
                    const std::vector<Vec3>& normals, const PassSettings& s) {
  auto& quadric = h.quadric;
  auto& flipping = h.flipping;
  auto& shading = h.shading;
  d.add(quadric);
  d.add(flipping);
  d.add(shading);
  d.module(shading).set(normals.empty() ? nullptr : &normals, s.shading_deg);
  if (s.fit) d.module(shading).set_fit(&mesh, &verts);
  d.module(quadric).set_max_err(s.bound * s.bound, false);
  d.module(flipping).set_max_normal_deviation(s.normal_deg);
  if (!d.initialize()) throw LibraryError("decimate: OpenMesh's decimater did not initialize");
}

// Decimates the faces `in` (vertex ids into mesh.positions) with the vertices `locked`
// (sorted) kept; appends the surviving faces (same vertex ids) to `out`, and counts the faces
// OpenMesh refused (kept unchanged in `out`).
void decimate_faces(const TriangleMesh& mesh, const FaceSet& in, const std::vector<std::uint32_t>& locked,
                    const PassSettings& settings, FaceSet& out, std::size_t& refused) {
  const std::vector<Triangle>& faces = in.tris;
  // Local vertex ids: the sorted distinct vertices of the faces.
  std::vector<std::uint32_t> verts;
  verts.reserve(faces.size() * 3 / 2 + 8);
  for (const Triangle& t : faces) verts.insert(verts.end(), t.begin(), t.end());
  std::sort(verts.begin(), verts.end());
  verts.erase(std::unique(verts.begin(), verts.end()), verts.end());
  const auto local = [&](std::uint32_t v) {
    return OmMesh::VertexHandle(int(std::lower_bound(verts.begin(), verts.end(), v) - verts.begin()));
  };
  const bool has_normals = mesh.normals.size() == mesh.positions.size();
  PassSettings s = settings;
  s.fit = s.fit && has_normals && s.shading_deg < 180.0;
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
  // The full mesh's shaded normals, by local vertex (ModShadingT's ring check).
  std::vector<Vec3> normals;
  if (!s.fit && s.shading_deg < 180.0 && has_normals) {
    normals.reserve(verts.size());
    for (std::uint32_t v : verts) normals.push_back(mesh.normals[v]);
  }
  std::vector<bool> lock(verts.size(), false);
  for (std::uint32_t v : locked)
    if (std::binary_search(verts.begin(), verts.end(), v)) lock[std::size_t(local(v).idx())] = true;
  std::vector<std::pair<OmMesh::FaceHandle, std::size_t>> added;  // face, index in `in`
  added.reserve(faces.size());
  for (std::size_t i = 0; i < faces.size(); ++i) {
    const Triangle& t = faces[i];
    const auto a = local(t[0]), b = local(t[1]), c = local(t[2]);
    const OmMesh::FaceHandle f = a == b || b == c || a == c ? OmMesh::FaceHandle() : om.add_face(a, b, c);
    if (!f.is_valid()) {
      out.push(t, i < in.points.size() ? in.points[i] : FacePoints{});  // refused: kept, its vertices locked
      ++refused;
      lock[std::size_t(a.idx())] = lock[std::size_t(b.idx())] = lock[std::size_t(c.idx())] = true;
    } else {
      added.emplace_back(f, i);
    }
  }
  for (const auto vh : om.vertices())
    if (lock[std::size_t(vh.idx())] || om.is_boundary(vh)) om.status(vh).set_locked(true);
  om.update_face_normals();
  const auto run = [&](auto& decimater) {
    DecimationModules modules;
    attach_modules(decimater, modules, mesh, verts, normals, s);
    auto& shading = decimater.module(modules.shading);
    if (s.fit)
      for (const auto& [f, i] : added)
        if (i < in.points.size()) shading.points(f) = in.points[i];
    if (s.bound > 0.0) {
      if constexpr (std::is_same_v<std::decay_t<decltype(decimater)>, SweepDecimater>)
        decimater.sweep(s.seed);
      else
        decimater.decimate(0);
    }
    for (const auto fh : om.faces()) {
      if (om.status(fh).deleted()) continue;
      auto fv = om.fv_iter(fh);
      Triangle t;
      for (int k = 0; k < 3; ++k, ++fv) t[std::size_t(k)] = verts[std::size_t(fv->idx())];
      out.push(t, s.fit ? std::move(shading.points(fh)) : FacePoints{});
    }
  };
  if (s.greedy) {
    SweepDecimater sweeper(om);
    run(sweeper);
  } else {
    OpenMesh::Decimater::DecimaterT<OmMesh> decimater(om);
    run(decimater);
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
  FaceSet kept;
  // OpenMesh's log streams are process-global; its stream buffers serialise writes, so the
  // chunks may run at once while this thread holds the capture.
  std::lock_guard<std::mutex> lock(detail::openmesh_mutex());
  detail::OpenMeshChatterCapture chatter;
  const std::size_t n = mesh.triangle_count();
  // Each pass gets half the bound: greedy sweeps first, then the heap.
  const auto pass = [&](bool greedy, std::uint64_t seed) {
    PassSettings p;
    p.bound = 0.5 * options.max_deviation;
    p.normal_deg = options.max_normal_deviation_deg;
    p.shading_deg = options.max_shading_deviation_deg;
    p.fit = options.shading_check == DecimationOptions::ShadingCheck::fit;
    p.greedy = greedy;
    p.seed = seed;
    return p;
  };
  if (options.chunk_triangles == 0 || n <= options.chunk_triangles) {
    // Greedy sweeps first (their own half of the bound), then the heap at the other half.
    FaceSet all, swept;
    all.tris = mesh.triangles;
    std::size_t refused = 0;
    decimate_faces(mesh, all, {}, pass(true, 1), swept, refused);
    decimate_faces(mesh, swept, {}, pass(false, 0), kept, result.unmanifold_kept);
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
    std::vector<FaceSet> outs(chunks);
    std::vector<std::size_t> refused(chunks, 0);
    tbb::parallel_for(std::size_t(0), chunks, [&](std::size_t c) {
      const std::size_t first = (c * n + chunks - 1) / chunks, last = ((c + 1) * n + chunks - 1) / chunks;
      FaceSet chunk;
      std::vector<Triangle>& faces = chunk.tris;
      faces.reserve(last - first);
      for (std::size_t r = first; r < last; ++r) faces.push_back(mesh.triangles[std::uint32_t(keyed[r])]);
      std::vector<std::uint32_t> locked;
      for (const Triangle& t : faces)
        for (std::uint32_t v : t)
          if (owner[v] == kShared) locked.push_back(v);
      std::sort(locked.begin(), locked.end());
      locked.erase(std::unique(locked.begin(), locked.end()), locked.end());
      decimate_faces(mesh, chunk, locked, pass(true, c + 1), outs[c], refused[c]);
    });
    FaceSet joined;
    for (auto& o : outs) joined.append(std::move(o));
    std::size_t refused_again = 0;
    decimate_faces(mesh, joined, {}, pass(false, 0), kept, refused_again);
    result.unmanifold_kept = refused_again;  // what the last pass could not take
  }
  // Compact the kept vertices.
  constexpr std::uint32_t kNone = 0xffffffffu;
  std::vector<std::uint32_t> remap(mesh.vertex_count(), kNone);
  const bool has_normals = mesh.normals.size() == mesh.positions.size();
  TriangleMesh& out = result.mesh;
  out.triangles.reserve(kept.tris.size());
  for (Triangle t : kept.tris) {
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
