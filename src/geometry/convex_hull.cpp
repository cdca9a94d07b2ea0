// Convex hull candidates through Qhull (libqhull_r, Debian's libqhull-dev). Its header's
// macros (True, False, FORALL..., trace...) stay in this file: it is built outside the unity
// batches (src/CMakeLists.txt).
#include "geometry/convex_hull.h"
#include <cstdio>
extern "C" {
#include <libqhull_r/qhull_ra.h>
}

namespace hb {

std::vector<Vec3> hull_candidates(const std::vector<Vec3>& points) {
  if (points.size() < 4096) return points;
  for (const Vec3& p : points)
    if (!p.allFinite()) return points;  // no hull of a non-finite point: the caller sees them all
  std::vector<coordT> coords(points.size() * 3);
  for (std::size_t k = 0; k < points.size(); ++k)
    for (int c = 0; c < 3; ++c) coords[3 * k + std::size_t(c)] = coordT(points[k][c]);
  static FILE* const quiet = std::fopen("/dev/null", "w");
  qhT qh_qh;
  qhT* qh = &qh_qh;
  qh_zero(qh, quiet);
  char options[] = "qhull Qc";
  const int failed = qh_new_qhull(qh, 3, int(points.size()), coords.data(), False, options, nullptr, quiet);
  std::vector<char> keep;
  if (!failed) {
    keep.assign(points.size(), 0);
    vertexT* vertex;
    FORALLvertices {
      const int id = qh_pointid(qh, vertex->point);
      if (id >= 0 && std::size_t(id) < points.size()) keep[std::size_t(id)] = 1;
    }
    facetT* facet;
    pointT *point, **pointp;
    FORALLfacets {
      FOREACHpoint_(facet->coplanarset) {
        const int id = qh_pointid(qh, point);
        if (id >= 0 && std::size_t(id) < points.size()) keep[std::size_t(id)] = 1;
      }
    }
  }
  qh_freeqhull(qh, !qh_ALL);
  int curlong = 0, totlong = 0;
  qh_memfreeshort(qh, &curlong, &totlong);
  if (keep.empty()) return points;
  std::vector<Vec3> out;
  for (std::size_t k = 0; k < points.size(); ++k)
    if (keep[k]) out.push_back(points[k]);
  return out.size() >= 4 ? out : points;
}

} // namespace hb
