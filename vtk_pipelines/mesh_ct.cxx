// The synthesized CT of a closed mesh:
//  1. The mesh is scaled to `length_mm` and placed in a limb (an elliptic cylinder with rounded
//     ends around its bounding box, along z) inside a box of air.
//  2. Its partial volume: subsamples^2 rays along x per voxel column, each crossing the mesh an
//     even number of times (odd: an open spot, the ray is dropped); the inside intervals are
//     added to the voxels they overlap, exactly along x. The limb's skin and fat are analytic
//     (a linear ramp one voxel wide across their surfaces).
//  3. Values: air, fat, muscle; bone = cortical near its surface, cancellous deeper (how deep is
//     read from the bone fraction blurred over a few millimetres). Then the point spread
//     (Gaussian blur) and Gaussian noise, rounded to signed 16-bit HU.
#include "mesh_ct.h"
#include "errors.h"
#include <vtkFloatArray.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkShortArray.h>
#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

namespace hb::vtk {

namespace {

vtkSmartPointer<vtkImageData> ct_float_image(const int dims[3]) {
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->SetDimensions(dims[0], dims[1], dims[2]);
  image->AllocateScalars(VTK_FLOAT, 1);
  std::fill_n(static_cast<float*>(image->GetScalarPointer()), image->GetNumberOfPoints(), 0.f);
  return image;
}

// A separable Gaussian blur (sigma in voxels, kernel to 3 sigma, edges clamped) of a float image.
vtkSmartPointer<vtkImageData> ct_gaussian(vtkImageData* in, double sigma_voxels) {
  const int* d = in->GetDimensions();
  auto out = ct_float_image(d);
  const int r = std::max(1, int(std::ceil(3.0 * sigma_voxels)));
  std::vector<double> kernel(static_cast<std::size_t>(2 * r + 1));
  double sum = 0.0;
  for (int t = -r; t <= r; ++t) sum += kernel[std::size_t(t + r)] = std::exp(-0.5 * t * t / (sigma_voxels * sigma_voxels));
  for (double& w : kernel) w /= sum;
  std::vector<float> a(static_cast<const float*>(in->GetScalarPointer()), static_cast<const float*>(in->GetScalarPointer()) + in->GetNumberOfPoints());
  std::vector<float> b(a.size());
  const std::size_t stride[3] = {1, std::size_t(d[0]), std::size_t(d[0]) * std::size_t(d[1])};
  for (int axis = 0; axis < 3; ++axis) {
    const int n = d[axis];
    for (std::size_t at = 0; at < a.size(); ++at) {
      const int i = int(at / stride[axis] % std::size_t(n));
      double v = 0.0;
      for (int t = -r; t <= r; ++t) {
        const int s = std::clamp(i + t, 0, n - 1);
        v += kernel[std::size_t(t + r)] * a[at + (std::ptrdiff_t(s) - i) * std::ptrdiff_t(stride[axis])];
      }
      b[at] = float(v);
    }
    a.swap(b);
  }
  std::copy(a.begin(), a.end(), static_cast<float*>(out->GetScalarPointer()));
  return out;
}

double skin_ramp(double signed_distance, double width) { return std::clamp(0.5 - signed_distance / width, 0.0, 1.0); }

}  // namespace

MeshCt make_mesh_ct(const TriangleMesh& mesh, const MeshCtOptions& o) {
  if (mesh.triangle_count() == 0) throw InvalidInput("make_mesh_ct: the mesh has no triangles");
  if (!(o.voxel_mm > 0.0) || !(o.length_mm > 0.0) || o.subsamples < 1)
    throw InvalidInput("make_mesh_ct: voxel size, length and subsamples must be positive");
  const Bounds b = mesh.bounds();
  const Vec3 extent = b.max - b.min;
  const double scale = o.length_mm / double(extent.maxCoeff());
  const double h = o.voxel_mm;

  // The limb around the bone (mm, the bone's bounding box centred at the origin first).
  const Eigen::Vector3d half = 0.5 * scale * extent.cast<double>();
  const double ax = half.x() + o.limb_margin_mm, ay = half.y() + o.limb_margin_mm;
  const double hz = half.z() + 0.5 * o.limb_margin_mm;
  const Eigen::Vector3d box_half(ax + o.air_margin_mm, ay + o.air_margin_mm, hz + o.air_margin_mm);
  int dims[3];
  for (int a = 0; a < 3; ++a) dims[a] = int(std::ceil(2.0 * box_half[a] / h)) + 1;
  // Voxel (i, j, k) is at origin + h (i, j, k); the limb's centre is at the origin of the mesh frame.
  const Eigen::Vector3d origin = -0.5 * h * Eigen::Vector3d(dims[0] - 1, dims[1] - 1, dims[2] - 1);
  MeshCt ct;
  ct.index_to_mm.setIdentity();
  ct.index_to_mm.topLeftCorner<3, 3>() *= h;
  ct.index_to_mm.block<3, 1>(0, 3) = origin;

  ct.source_mm = mesh;
  const Eigen::Vector3d centre = 0.5 * (b.min + b.max).cast<double>();
  for (Vec3& p : ct.source_mm.positions) p = ((p.cast<double>() - centre) * scale).cast<float>();
  ct.source_mm.compute_vertex_normals();
  const std::vector<Vec3>& P = ct.source_mm.positions;

  // 2. Triangles binned by the (j, k) voxel columns their y-z extent overlaps.
  const int ny = dims[1], nz = dims[2], nx = dims[0];
  std::vector<std::vector<std::uint32_t>> bins(std::size_t(ny) * nz);
  for (std::uint32_t t = 0; t < mesh.triangle_count(); ++t) {
    const auto& tri = ct.source_mm.triangles[t];
    double lo[2] = {1e300, 1e300}, hi[2] = {-1e300, -1e300};
    for (int c = 0; c < 3; ++c)
      for (int a = 0; a < 2; ++a) {
        const double v = P[tri[c]][a + 1];
        lo[a] = std::min(lo[a], v);
        hi[a] = std::max(hi[a], v);
      }
    const int j0 = std::max(0, int(std::floor((lo[0] - origin.y()) / h + 0.5))), j1 = std::min(ny - 1, int(std::floor((hi[0] - origin.y()) / h + 0.5)));
    const int k0 = std::max(0, int(std::floor((lo[1] - origin.z()) / h + 0.5))), k1 = std::min(nz - 1, int(std::floor((hi[1] - origin.z()) / h + 0.5)));
    for (int k = k0; k <= k1; ++k)
      for (int j = j0; j <= j1; ++j) bins[std::size_t(k) * ny + j].push_back(t);
  }
  auto bone = ct_float_image(dims);
  float* B = static_cast<float*>(bone->GetScalarPointer());
  const int S = o.subsamples;
  std::vector<double> column(static_cast<std::size_t>(nx)), crossings;
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j) {
      const auto& list = bins[std::size_t(k) * ny + j];
      if (list.empty()) continue;
      std::fill(column.begin(), column.end(), 0.0);
      int valid = 0;
      for (int sk = 0; sk < S; ++sk)
        for (int sj = 0; sj < S; ++sj) {
          // Off the lattice by an irrational fraction: no ray runs through an edge or a vertex.
          const double y = origin.y() + h * (j - 0.5 + (sj + 0.5) / S + 1.3e-4 * std::sqrt(2.0));
          const double z = origin.z() + h * (k - 0.5 + (sk + 0.5) / S + 1.1e-4 * std::sqrt(3.0));
          crossings.clear();
          for (std::uint32_t t : list) {
            const auto& tri = ct.source_mm.triangles[t];
            const Eigen::Vector3d a = P[tri[0]].cast<double>(), bb = P[tri[1]].cast<double>(), c = P[tri[2]].cast<double>();
            // Barycentric coordinates of (y, z) in the triangle's projection on the y-z plane.
            const double d = (bb.y() - a.y()) * (c.z() - a.z()) - (c.y() - a.y()) * (bb.z() - a.z());
            if (d == 0.0) continue;
            const double u = ((y - a.y()) * (c.z() - a.z()) - (c.y() - a.y()) * (z - a.z())) / d;
            const double v = ((bb.y() - a.y()) * (z - a.z()) - (y - a.y()) * (bb.z() - a.z())) / d;
            if (u < 0.0 || v < 0.0 || u + v > 1.0) continue;
            crossings.push_back(a.x() + u * (bb.x() - a.x()) + v * (c.x() - a.x()));
          }
          if (crossings.size() % 2 != 0) {
            ++ct.rays_dropped;
            continue;
          }
          ++valid;
          std::sort(crossings.begin(), crossings.end());
          for (std::size_t c = 0; c + 1 < crossings.size(); c += 2) {
            const double x0 = (crossings[c] - origin.x()) / h + 0.5, x1 = (crossings[c + 1] - origin.x()) / h + 0.5;
            for (int i = std::max(0, int(std::floor(x0))); i <= std::min(nx - 1, int(std::floor(x1))); ++i)
              column[std::size_t(i)] += std::max(0.0, std::min(x1, i + 1.0) - std::max(x0, double(i)));
          }
        }
      if (valid == 0) continue;
      for (int i = 0; i < nx; ++i) B[(std::size_t(k) * ny + j) * nx + i] = float(column[std::size_t(i)] / valid);
    }
  if (ct.rays_dropped > S * S * ny * nz / 100)
    throw InvalidInput("make_mesh_ct: the mesh is not closed (" + std::to_string(ct.rays_dropped) +
                       " rays cross it an odd number of times)");

  // 3. Values. Depth into the bone from its fraction blurred over the cortical depth.
  auto deep = ct_gaussian(bone, o.cortical_mm / 1.4 / h);
  const float* D = static_cast<const float*>(deep->GetScalarPointer());
  auto hu = ct_float_image(dims);
  float* V = static_cast<float*>(hu->GetScalarPointer());
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        const Eigen::Vector3d p = origin + h * Eigen::Vector3d(i, j, k);
        const double dr = (std::sqrt(p.x() * p.x() / (ax * ax) + p.y() * p.y() / (ay * ay)) - 1.0) * std::min(ax, ay);
        const double dz = std::abs(p.z()) - hz;
        const double skin = std::hypot(std::max(dr, 0.0), std::max(dz, 0.0)) + std::min(std::max(dr, dz), 0.0);
        const double body = skin_ramp(skin, h), muscle = skin_ramp(skin + o.fat_mm, h);
        const std::size_t at = (std::size_t(k) * ny + j) * nx + i;
        const double inner = std::clamp((double(D[at]) - 0.9) / 0.08, 0.0, 1.0);
        const double bone_hu = o.cortical_hu + inner * (o.cancellous_hu - o.cortical_hu);
        V[at] = float(o.air_hu + body * (o.fat_hu - o.air_hu) + muscle * (o.muscle_hu - o.fat_hu) + B[at] * (bone_hu - o.muscle_hu));
      }
  deep = nullptr;
  bone = nullptr;
  auto blurred = ct_gaussian(hu, o.psf_sigma_mm / h);
  hu = nullptr;
  const float* W = static_cast<const float*>(blurred->GetScalarPointer());
  ct.image = vtkSmartPointer<vtkImageData>::New();
  ct.image->SetDimensions(dims);
  ct.image->AllocateScalars(VTK_SHORT, 1);
  auto* out = static_cast<short*>(ct.image->GetScalarPointer());
  std::mt19937 random(o.seed);
  std::normal_distribution<double> noise(0.0, o.noise_hu);
  for (vtkIdType n = 0; n < ct.image->GetNumberOfPoints(); ++n)
    out[n] = short(std::clamp(std::lround(W[n] + noise(random)), -1024L, 3071L));
  return ct;
}

} // namespace hb::vtk
