#pragma once
// The core's 3-vector: positions, directions, normals and forces in model units or SI units.
// A small header of its own so that layers which need only vectors (device/, geometry/)
// include no mesh.
#include <Eigen/Core>
#include <Eigen/Geometry>  // cross()

namespace hb {

using Vec3 = Eigen::Vector3f;
using Vec3d = Eigen::Vector3d;  ///< device space (m) and the simulations in it.

} // namespace hb
