// Automatic decomposition (see the header for the contract).
//  1. Leaves: recursive median split of triangle centroids along the longest axis of their
//     bounds (ties broken by triangle id) down to ~T/leaves triangles; every leaf is split into
//     edge-connected components. Each component is a cluster.
//  2. Lines: `lines` isotropic uniform lines through the bounding sphere (radius R), every
//     crossing collected with repeated Embree rays. Lines with fewer than two crossings can
//     hold no pocket and are dropped. Each cluster keeps the sorted list of lines it meets.
//  3. Pocket probability of a piece = (sum over lines of its pocket length, line_pockets)
//     / (expected sum of chords in its box) where, for isotropic lines, the latter is
//     lines * V(box) / (pi R^2). The box is the PCA box of the piece (area moments, which
//     add up under merging) over a few extreme points per piece (26 fixed directions).
//     Merging a and b changes pocket lengths only on lines meeting both, so a candidate is
//     evaluated on the intersection of their line lists.
//  4. Greedy merging with a lazy priority queue (stale entries carry old versions).
//  5. Small pieces, then max_pieces, then relabelling by lowest triangle id.
#include "decomposition/auto_decomposition.h"
#include "decomposition/pocket_measure.h"
#include "errors.h"
#include "exact/embree_scene.h"
#include "mesh/triangle_adjacency.h"
#include <Eigen/Eigenvalues>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numeric>
#include <optional>
#include <queue>
#include <random>

namespace hb {
namespace {

constexpr int kDirections = 13;
const Vec3& fixed_direction(int k) {
  static const Vec3 dirs[kDirections] = {
      Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1),
      Vec3(1, 1, 0).normalized(), Vec3(1, -1, 0).normalized(), Vec3(1, 0, 1).normalized(),
      Vec3(1, 0, -1).normalized(), Vec3(0, 1, 1).normalized(), Vec3(0, 1, -1).normalized(),
      Vec3(1, 1, 1).normalized(), Vec3(1, 1, -1).normalized(), Vec3(1, -1, 1).normalized(),
      Vec3(-1, 1, 1).normalized()};
  return dirs[k];
}

// Additive shape summary of a set of triangles.
struct Shape {
  double area = 0.0;
  Eigen::Vector3d first = Eigen::Vector3d::Zero();   // sum area * centroid
  Eigen::Matrix3d second = Eigen::Matrix3d::Zero();  // sum of integral x x^T
  Vec3 extreme[2 * kDirections];                     // min and max point along each direction
  // extreme[i].dot(its direction), kept rather than recomputed: build_pieces adds every
  // triangle's 26 extremes, and the 4 dot products a point and direction cost were most of
  // the 13M-triangle decomposition (47 s of 92). The same floats as recomputing them.
  float extreme_dot[2 * kDirections];
  bool empty = true;

  void add_point(const Vec3& p) {
    for (int k = 0; k < kDirections; ++k) {
      const float d = p.dot(fixed_direction(k));
      if (empty || d < extreme_dot[2 * k]) extreme[2 * k] = p, extreme_dot[2 * k] = d;
      if (empty || d > extreme_dot[2 * k + 1]) extreme[2 * k + 1] = p, extreme_dot[2 * k + 1] = d;
    }
    empty = false;
  }
  void add(const Shape& o) {
    area += o.area;
    first += o.first;
    second += o.second;
    for (const Vec3& p : o.extreme)
      if (!o.empty) add_point(p);
  }
  // Volume of the padded PCA box over the extreme points (padding as fit_obb's default).
  double box_volume() const {
    Eigen::Matrix3f axes = Eigen::Matrix3f::Identity();
    if (area > 0.0) {
      const Eigen::Vector3d mean = first / area;
      const Eigen::Matrix3d cov = second / area - mean * mean.transpose();
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(cov);
      if (solver.info() == Eigen::Success) axes = solver.eigenvectors().cast<float>();
    }
    Vec3 lo = Vec3::Constant(1e30f), hi = Vec3::Constant(-1e30f);
    for (const Vec3& p : extreme) {
      const Vec3 q = axes.transpose() * p;
      lo = lo.cwiseMin(q);
      hi = hi.cwiseMax(q);
    }
    Vec3 size = (hi - lo).cwiseMax(0.f);
    const float pad = 0.02f * size.norm();
    size.array() += 2.f * pad;
    return double(size.x()) * double(size.y()) * double(size.z());
  }
};

Shape triangle_shape(const TriangleMesh& mesh, std::uint32_t t) {
  Shape s;
  const Triangle& tri = mesh.triangles[t];
  const Eigen::Vector3d a = mesh.positions[tri[0]].cast<double>();
  const Eigen::Vector3d b = mesh.positions[tri[1]].cast<double>();
  const Eigen::Vector3d c = mesh.positions[tri[2]].cast<double>();
  const double area = 0.5 * (b - a).cross(c - a).norm();
  const Eigen::Vector3d centroid = (a + b + c) / 3.0;
  s.area = area;
  s.first = area * centroid;
  s.second = area / 12.0 * (9.0 * centroid * centroid.transpose() + a * a.transpose() + b * b.transpose() +
                            c * c.transpose());
  for (auto v : tri) s.add_point(mesh.positions[v]);
  return s;
}

// 1. Leaves of the median-split tree.
void split_leaves(const std::vector<Vec3>& centroids, std::uint32_t* first, std::uint32_t* last,
                  std::size_t leaf_size, std::vector<std::pair<std::uint32_t*, std::uint32_t*>>& leaves) {
  const std::size_t count = std::size_t(last - first);
  if (count <= leaf_size) {
    leaves.emplace_back(first, last);
    return;
  }
  Vec3 lo = Vec3::Constant(1e30f), hi = Vec3::Constant(-1e30f);
  for (auto* p = first; p != last; ++p) {
    lo = lo.cwiseMin(centroids[*p]);
    hi = hi.cwiseMax(centroids[*p]);
  }
  int axis = 0;
  (hi - lo).maxCoeff(&axis);
  std::uint32_t* mid = first + count / 2;
  std::nth_element(first, mid, last, [&](std::uint32_t a, std::uint32_t b) {
    const float ca = centroids[a][axis], cb = centroids[b][axis];
    return ca < cb || (ca == cb && a < b);
  });
  split_leaves(centroids, first, mid, leaf_size, leaves);
  split_leaves(centroids, mid, last, leaf_size, leaves);
}

struct Piece {
  Shape shape;
  std::vector<std::uint32_t> clusters;
  std::vector<std::uint32_t> lines;       // sorted ids of lines meeting the piece
  std::vector<std::uint32_t> neighbours;  // sorted ids of adjacent live pieces
  double pocket_length = 0.0;
  std::size_t triangles = 0;
  std::uint32_t version = 0;
  bool alive = true;
};

struct Candidate {
  double cost;
  std::size_t size;
  std::uint32_t a, b, version_a, version_b;
  double pocket_length;
  bool operator>(const Candidate& o) const {
    if (cost != o.cost) return cost > o.cost;
    if (size != o.size) return size > o.size;
    if (a != o.a) return a > o.a;
    return b > o.b;
  }
};

class Merger {
public:
  Merger(const TriangleMesh& mesh, const AutoDecompositionOptions& options, const EmbreeScene* scene)
      : mesh_(mesh), options_(options), scene_(scene) {}

  Decomposition run();

private:
  void build_clusters();
  void build_lines();
  void build_pieces();
  Candidate evaluate(std::uint32_t a, std::uint32_t b) const;
  double pocket_on_line(std::uint32_t line, std::uint32_t a, std::uint32_t b) const;
  void merge(const Candidate& c);
  void push_neighbours(std::uint32_t a);
  bool report(double fraction) const {
    if (options_.progress && !options_.progress(fraction)) throw Cancelled("decomposition cancelled");
    return true;
  }

  const TriangleMesh& mesh_;
  const AutoDecompositionOptions& options_;
  const EmbreeScene* scene_;  // given (shared with the caller) or null: build_lines builds one
  TriangleAdjacency adjacency_;
  std::vector<std::uint32_t> cluster_of_triangle_;
  std::vector<std::vector<std::uint32_t>> cluster_triangles_;
  // Lines: crossings in compressed rows, cluster per crossing.
  std::vector<std::uint32_t> line_offsets_;
  std::vector<LineHit> hits_;
  std::vector<std::uint32_t> hit_cluster_;
  std::vector<std::vector<std::uint32_t>> cluster_lines_;
  double chord_scale_ = 0.0;  // expected chord sum per unit box volume
  std::vector<std::uint32_t> piece_of_cluster_;
  std::vector<Piece> pieces_;
  std::size_t alive_ = 0;
  std::priority_queue<Candidate, std::vector<Candidate>, std::greater<Candidate>> queue_;
};

void Merger::build_clusters() {
  const std::size_t count = mesh_.triangle_count();
  adjacency_ = triangle_adjacency(mesh_);
  std::vector<Vec3> centroids(count);
  for (std::size_t t = 0; t < count; ++t) {
    const Triangle& tri = mesh_.triangles[t];
    centroids[t] = (mesh_.positions[tri[0]] + mesh_.positions[tri[1]] + mesh_.positions[tri[2]]) / 3.f;
  }
  std::vector<std::uint32_t> order(count);
  std::iota(order.begin(), order.end(), 0u);
  const std::size_t leaf_size = std::max<std::size_t>(8, count / std::size_t(std::max(1, options_.leaves)) + 1);
  std::vector<std::pair<std::uint32_t*, std::uint32_t*>> leaves;
  split_leaves(centroids, order.data(), order.data() + count, leaf_size, leaves);
  std::vector<std::uint32_t> leaf_of(count);
  for (std::uint32_t l = 0; l < leaves.size(); ++l)
    for (auto* p = leaves[l].first; p != leaves[l].second; ++p) leaf_of[*p] = l;
  // Connected components inside each leaf, seeded in triangle order.
  cluster_of_triangle_.assign(count, UINT32_MAX);
  std::vector<std::uint32_t> stack;
  for (std::uint32_t seed = 0; seed < count; ++seed) {
    if (cluster_of_triangle_[seed] != UINT32_MAX) continue;
    const std::uint32_t id = std::uint32_t(cluster_triangles_.size());
    cluster_triangles_.emplace_back();
    cluster_of_triangle_[seed] = id;
    stack.assign(1, seed);
    while (!stack.empty()) {
      const std::uint32_t t = stack.back();
      stack.pop_back();
      cluster_triangles_[id].push_back(t);
      for (const std::uint32_t* n = adjacency_.begin(t); n != adjacency_.end(t); ++n)
        if (cluster_of_triangle_[*n] == UINT32_MAX && leaf_of[*n] == leaf_of[t]) {
          cluster_of_triangle_[*n] = id;
          stack.push_back(*n);
        }
    }
    std::sort(cluster_triangles_[id].begin(), cluster_triangles_[id].end());
  }
}

void Merger::build_lines() {
  const Bounds b = mesh_.bounds();
  const Vec3 centre = 0.5f * (b.min + b.max);
  const float radius = 0.5f * b.diagonal() * 1.01f + 1e-6f;
  const int count = options_.lines;
  chord_scale_ = double(count) / (M_PI * double(radius) * double(radius));
  std::optional<EmbreeScene> own;
  const EmbreeScene& scene = scene_ ? *scene_ : own.emplace(mesh_);
  std::vector<std::vector<LineHit>> per_line(static_cast<std::size_t>(count));
  const float eps = 1e-6f * radius;
  std::mt19937_64 base(options_.seed);
  const std::uint64_t seed = base();
  // In chunks, with progress (0.05 to 0.3) and a chance to cancel between them: the lines are
  // a large share of the decomposition's time. Line i depends only on i: same lines whatever
  // the chunking.
  constexpr int kChunks = 24;
  const int chunk = std::max(1024, (count + kChunks - 1) / kChunks);
  for (int from = 0; from < count; from += chunk) {
  const int to = std::min(count, from + chunk);
  tbb::parallel_for(tbb::blocked_range<int>(from, to, 1024), [&](const tbb::blocked_range<int>& r) {
    std::vector<LineHit> hits;
    for (int i = r.begin(); i != r.end(); ++i) {
      std::mt19937_64 rng(seed ^ (std::uint64_t(i) * 0x9E3779B97F4A7C15ull));
      std::uniform_real_distribution<double> uni(0.0, 1.0);
      const double z = 2.0 * uni(rng) - 1.0, phi = 2.0 * M_PI * uni(rng);
      const double s = std::sqrt(std::max(0.0, 1.0 - z * z));
      const Vec3 dir(float(s * std::cos(phi)), float(s * std::sin(phi)), float(z));
      const Vec3 helper = std::fabs(dir.x()) < 0.9f ? Vec3::UnitX() : Vec3::UnitY();
      const Vec3 e1 = dir.cross(helper).normalized();
      const Vec3 e2 = dir.cross(e1);
      const double rr = radius * std::sqrt(uni(rng)), a = 2.0 * M_PI * uni(rng);
      const Vec3 origin = centre + float(rr * std::cos(a)) * e1 + float(rr * std::sin(a)) * e2 - radius * dir;
      hits.clear();
      collect_line_hits(scene, origin, dir, 2.f * radius, eps, hits);
      if (hits.size() >= 2) per_line[std::size_t(i)] = hits;
    }
  });
  report(0.05 + 0.25 * double(to) / double(count));
  }
  line_offsets_.assign(1, 0);
  cluster_lines_.assign(cluster_triangles_.size(), {});
  for (const auto& hits : per_line) {
    if (hits.empty()) continue;
    const std::uint32_t line = std::uint32_t(line_offsets_.size() - 1);
    for (const LineHit& h : hits) {
      hits_.push_back(h);
      const std::uint32_t c = cluster_of_triangle_[h.triangle];
      hit_cluster_.push_back(c);
      auto& list = cluster_lines_[c];
      if (list.empty() || list.back() != line) list.push_back(line);
    }
    line_offsets_.push_back(std::uint32_t(hits_.size()));
  }
}

double Merger::pocket_on_line(std::uint32_t line, std::uint32_t a, std::uint32_t b) const {
  const std::uint32_t first = line_offsets_[line], last = line_offsets_[line + 1];
  const std::uint32_t* cl = hit_cluster_.data();
  const auto* pc = piece_of_cluster_.data();
  const LineHit* base = hits_.data() + first;
  return line_pockets(base, last - first, [&](const LineHit& h) {
           const std::uint32_t p = pc[cl[std::size_t(&h - hits_.data())]];
           return p == a || p == b;
         }).length;
}

void Merger::build_pieces() {
  const std::size_t count = cluster_triangles_.size();
  pieces_.resize(count);
  piece_of_cluster_.resize(count);
  std::iota(piece_of_cluster_.begin(), piece_of_cluster_.end(), 0u);
  tbb::parallel_for(std::size_t(0), count, [&](std::size_t c) {
    Piece& p = pieces_[c];
    p.clusters.assign(1, std::uint32_t(c));
    p.triangles = cluster_triangles_[c].size();
    for (std::uint32_t t : cluster_triangles_[c]) p.shape.add(triangle_shape(mesh_, t));
    p.lines = cluster_lines_[c];
    double length = 0.0;
    for (std::uint32_t line : p.lines) length += pocket_on_line(line, std::uint32_t(c), std::uint32_t(c));
    p.pocket_length = length;
    std::vector<std::uint32_t> nb;
    for (std::uint32_t t : cluster_triangles_[c])
      for (const std::uint32_t* n = adjacency_.begin(t); n != adjacency_.end(t); ++n)
        if (cluster_of_triangle_[*n] != c) nb.push_back(cluster_of_triangle_[*n]);
    std::sort(nb.begin(), nb.end());
    nb.erase(std::unique(nb.begin(), nb.end()), nb.end());
    p.neighbours = std::move(nb);
  });
  alive_ = count;
  cluster_lines_.clear();
}

Candidate Merger::evaluate(std::uint32_t a, std::uint32_t b) const {
  const Piece& pa = pieces_[a];
  const Piece& pb = pieces_[b];
  // Lines meeting both (intersection of sorted lists; search the smaller in the larger).
  const auto& small = pa.lines.size() <= pb.lines.size() ? pa.lines : pb.lines;
  const auto& large = pa.lines.size() <= pb.lines.size() ? pb.lines : pa.lines;
  double delta = 0.0;
  auto from = large.begin();
  for (std::uint32_t line : small) {
    from = std::lower_bound(from, large.end(), line);
    if (from == large.end()) break;
    if (*from != line) continue;
    delta += pocket_on_line(line, a, b) - pocket_on_line(line, a, a) - pocket_on_line(line, b, b);
  }
  Shape shape = pa.shape;
  shape.add(pb.shape);
  const double length = std::max(0.0, pa.pocket_length + pb.pocket_length + delta);
  const double chords = chord_scale_ * shape.box_volume();
  Candidate c;
  c.cost = chords > 0.0 ? length / chords : 0.0;
  c.size = pa.triangles + pb.triangles;
  c.a = std::min(a, b);
  c.b = std::max(a, b);
  c.version_a = pieces_[c.a].version;
  c.version_b = pieces_[c.b].version;
  c.pocket_length = length;
  return c;
}

void Merger::push_neighbours(std::uint32_t a) {
  const auto& nb = pieces_[a].neighbours;
  std::vector<Candidate> out(nb.size());
  tbb::parallel_for(std::size_t(0), nb.size(), [&](std::size_t k) { out[k] = evaluate(a, nb[k]); });
  for (const Candidate& c : out) queue_.push(c);
}

void Merger::merge(const Candidate& c) {
  Piece& pa = pieces_[c.a];
  Piece& pb = pieces_[c.b];
  for (std::uint32_t cl : pb.clusters) piece_of_cluster_[cl] = c.a;
  pa.clusters.insert(pa.clusters.end(), pb.clusters.begin(), pb.clusters.end());
  pa.shape.add(pb.shape);
  std::vector<std::uint32_t> lines;
  lines.reserve(pa.lines.size() + pb.lines.size());
  std::set_union(pa.lines.begin(), pa.lines.end(), pb.lines.begin(), pb.lines.end(), std::back_inserter(lines));
  pa.lines = std::move(lines);
  pa.pocket_length = c.pocket_length;
  pa.triangles += pb.triangles;
  std::vector<std::uint32_t> nb;
  std::set_union(pa.neighbours.begin(), pa.neighbours.end(), pb.neighbours.begin(), pb.neighbours.end(),
                 std::back_inserter(nb));
  nb.erase(std::remove_if(nb.begin(), nb.end(), [&](std::uint32_t x) { return x == c.a || x == c.b; }), nb.end());
  pa.neighbours = std::move(nb);
  for (std::uint32_t n : pa.neighbours) {
    auto& list = pieces_[n].neighbours;
    list.erase(std::remove(list.begin(), list.end(), c.b), list.end());
    auto it = std::lower_bound(list.begin(), list.end(), c.a);
    if (it == list.end() || *it != c.a) list.insert(it, c.a);
  }
  ++pa.version;
  pb.alive = false;
  ++pb.version;
  pb.clusters.clear();
  pb.clusters.shrink_to_fit();
  pb.lines.clear();
  pb.lines.shrink_to_fit();
  pb.neighbours.clear();
  --alive_;
}

Decomposition Merger::run() {
  // Each phase's end to options.on_phase (a diagnostic for large meshes: the budgeted bake's
  // stage times show the decomposition as one figure).
  const auto tq = std::chrono::steady_clock::now();
  const auto lap = [&](const char* what) {
    if (options_.on_phase) options_.on_phase(what, std::chrono::duration<double>(std::chrono::steady_clock::now() - tq).count());
  };
  report(0.0);
  build_clusters();
  lap("clusters");
  report(0.05);
  build_lines();
  lap("lines");
  report(0.3);
  build_pieces();
  lap("pieces");
  report(0.4);
  {
    std::vector<std::pair<std::uint32_t, std::uint32_t>> edges;
    for (std::uint32_t a = 0; a < pieces_.size(); ++a)
      for (std::uint32_t b : pieces_[a].neighbours)
        if (b > a) edges.emplace_back(a, b);
    std::vector<Candidate> out(edges.size());
    const std::size_t chunk = std::max<std::size_t>(256, edges.size() / 16 + 1);
    for (std::size_t from = 0; from < edges.size(); from += chunk) {
      const std::size_t to = std::min(edges.size(), from + chunk);
      tbb::parallel_for(from, to, [&](std::size_t k) { out[k] = evaluate(edges[k].first, edges[k].second); });
      report(0.4 + 0.1 * double(to) / double(edges.size()));
    }
    for (const Candidate& c : out) queue_.push(c);
  }
  const double total_area = [&] {
    double s = 0.0;
    for (const Piece& p : pieces_) s += p.shape.area;
    return s;
  }();
  const std::size_t start_count = alive_;
  // Phase 1: merges within the threshold; Phase 2: small pieces; Phase 3: max_pieces.
  auto stale = [&](const Candidate& c) {
    return !pieces_[c.a].alive || !pieces_[c.b].alive || pieces_[c.a].version != c.version_a ||
           pieces_[c.b].version != c.version_b;
  };
  auto small = [&](std::uint32_t p) { return pieces_[p].shape.area < options_.min_area_fraction * total_area; };
  std::vector<Candidate> deferred;
  while (!queue_.empty()) {
    const Candidate c = queue_.top();
    queue_.pop();
    if (stale(c)) continue;
    if (c.cost > options_.threshold) {
      deferred.push_back(c);
      continue;
    }
    merge(c);
    push_neighbours(c.a);
    if ((start_count - alive_) % 32 == 0) report(0.5 + 0.35 * double(start_count - alive_) / double(start_count));
  }
  // Phase 2 and 3 share one queue of the remaining candidates: a candidate is taken when one
  // side is small, or when there are still too many pieces (cheapest first).
  for (const Candidate& c : deferred)
    if (!stale(c)) queue_.push(c);
  bool changed = true;
  while (changed) {
    changed = false;
    std::vector<Candidate> keep;
    while (!queue_.empty()) {
      const Candidate c = queue_.top();
      queue_.pop();
      if (stale(c)) continue;
      if (small(c.a) || small(c.b) || alive_ > std::size_t(options_.max_pieces)) {
        merge(c);
        push_neighbours(c.a);
        changed = true;
        if (alive_ % 8 == 0) report(0.85 + 0.1 * double(start_count - alive_) / double(std::max<std::size_t>(start_count, 1)));
      } else {
        keep.push_back(c);
      }
    }
    for (const Candidate& c : keep)
      if (!stale(c)) queue_.push(c);
  }
  // Disconnected parts with no adjacency left: join the nearest pieces (by centroid).
  while (alive_ > std::size_t(options_.max_pieces)) {
    std::vector<std::uint32_t> live;
    for (std::uint32_t p = 0; p < pieces_.size(); ++p)
      if (pieces_[p].alive) live.push_back(p);
    double best = 1e300;
    Candidate pick{};
    for (std::size_t i = 0; i < live.size(); ++i)
      for (std::size_t j = i + 1; j < live.size(); ++j) {
        const auto& si = pieces_[live[i]].shape;
        const auto& sj = pieces_[live[j]].shape;
        const double d = (si.first / si.area - sj.first / sj.area).squaredNorm();
        if (d < best) {
          best = d;
          pick = evaluate(live[i], live[j]);
        }
      }
    merge(pick);
  }
  lap("merged");
  report(0.97);

  // Relabel by lowest triangle id.
  Decomposition out;
  const std::size_t count = mesh_.triangle_count();
  out.piece_of_triangle.assign(count, UINT32_MAX);
  std::vector<std::uint32_t> label(pieces_.size(), UINT32_MAX);
  for (std::uint32_t t = 0; t < count; ++t) {
    const std::uint32_t p = piece_of_cluster_[cluster_of_triangle_[t]];
    if (label[p] == UINT32_MAX) {
      label[p] = std::uint32_t(out.piece_count++);
      const double chords = chord_scale_ * pieces_[p].shape.box_volume();
      out.estimated_probability.push_back(chords > 0.0 ? pieces_[p].pocket_length / chords : 0.0);
    }
    out.piece_of_triangle[t] = label[p];
  }
  report(1.0);
  return out;
}

} // namespace

Decomposition decompose_auto(const TriangleMesh& mesh, const AutoDecompositionOptions& options, const EmbreeScene* scene) {
  if (mesh.triangle_count() == 0) throw InvalidInput("decompose_auto: mesh has no triangles");
  if (!(options.threshold >= 0.0 && options.threshold <= 1.0))
    throw InvalidInput("decompose_auto: threshold must be in [0, 1]");
  if (!(options.min_area_fraction >= 0.0 && options.min_area_fraction < 1.0))
    throw InvalidInput("decompose_auto: min_area_fraction must be in [0, 1)");
  if (options.max_pieces < 1) throw InvalidInput("decompose_auto: max_pieces must be >= 1");
  if (options.leaves < 1) throw InvalidInput("decompose_auto: leaves must be >= 1");
  if (options.lines < 1000) throw InvalidInput("decompose_auto: lines must be >= 1000");
  if (scene && (&scene->mesh() != &mesh))
    throw InvalidInput("decompose_auto: the Embree scene given is of another mesh");
  Merger merger(mesh, options, scene);
  return merger.run();
}

} // namespace hb
