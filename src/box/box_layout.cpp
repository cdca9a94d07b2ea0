// The box layout (box_layout.h): face frames, sample directions, box-local constants.
#include "box/box_layout.h"

namespace hb {

BoxLayout::BoxLayout(const Obb& obb, const BoxParams& params) noexcept : obb_(obb), params_(params) {
  for (int a = 0; a < 3; ++a) {
    for (int k = 0; k < 3; ++k) local_.rt[a][k] = obb_.axes(k, a);
    local_.center[a] = obb_.center[a];
    local_.half[a] = obb_.half[a];
    local_.grid_scale[a] = 0.5f * float(params_.m - 1) / obb_.half[a];
  }
  const float step = 2.f / float(params_.m - 1);
  for (int face = 0; face < 6; ++face) {
    const FaceAxes fa = face_axes(face);
    Vec3 local;
    local[fa.a] = fa.sign * obb_.half[fa.a];
    local[fa.u] = -obb_.half[fa.u];
    local[fa.v] = -obb_.half[fa.v];
    faces_[face].origin = obb_.to_world(local);
    faces_[face].step_i = obb_.axes.col(fa.u) * (obb_.half[fa.u] * step);
    faces_[face].step_j = obb_.axes.col(fa.v) * (obb_.half[fa.v] * step);
  }
}

Vec3 BoxLayout::sample_direction(int face, int sub, int sface, int a, int b) const noexcept {
  const FaceAxes fa = face_axes(face);
  const float c1 = float(a) / float(params_.n - 1), c2 = float(b) / float(params_.n - 1);
  float X, Y, Z;
  if (sface == 0) {
    X = c1; Y = c2; Z = 1.f;
  } else if (sface == 1) {
    X = 1.f; Y = c1; Z = c2;
  } else {
    X = c1; Y = 1.f; Z = c2;
  }
  const float x = (sub & 1) ? -X : X;
  const float y = (sub & 2) ? -Y : Y;
  Vec3 local;
  local[fa.u] = x;
  local[fa.v] = y;
  local[fa.a] = -fa.sign * Z;  // into the box
  return (obb_.axes * local).normalized();
}

} // namespace hb
