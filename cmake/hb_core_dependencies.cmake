# The libraries hb_core is built with and links (included by the top-level CMakeLists.txt and by
# the ParaView plugin's own project, which links the main build's hb_core).
find_package(Eigen3 3.3 REQUIRED NO_MODULE)
find_package(embree 3 REQUIRED)
find_package(TBB REQUIRED)
find_package(OpenMesh REQUIRED)
find_package(PkgConfig REQUIRED)
pkg_check_modules(XXHASH REQUIRED IMPORTED_TARGET libxxhash)
pkg_check_modules(QHULL REQUIRED IMPORTED_TARGET qhull_r)
find_package(nlohmann_json 3 REQUIRED)
