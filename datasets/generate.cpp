// Writes the generated test objects (paper section 6) into a folder:
// bumpy_sphere.off (default BumpySphereOptions) and chess_piece.off (default ChessPieceOptions).
// Usage: hb_generate_datasets OUTPUT_DIR. Exit 2 for usage, 1 for failure.
#include "errors.h"
#include "mesh/generators.h"
#include "mesh/mesh_io.h"

#include <filesystem>
#include <iostream>

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: " << argv[0] << " OUTPUT_DIR\n";
    return 2;
  }
  const std::filesystem::path dir(argv[1]);
  try {
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (ec) throw hb::IoError(dir.string() + ": cannot create folder (" + ec.message() + ")");
    const auto save = [&](const hb::TriangleMesh& mesh, const char* name) {
      const std::string path = (dir / name).string();
      hb::write_mesh(mesh, path);
      std::cout << "hb_generate_datasets: " << path << ": " << mesh.triangle_count() << " triangles, "
                << mesh.vertex_count() << " vertices\n";
    };
    save(hb::make_bumpy_sphere(), "bumpy_sphere.off");
    save(hb::make_chess_piece(), "chess_piece.off");
    // A second smooth, finely tessellated, quasi-convex object: an ellipsoid of
    // semi-axes 1, 0.75, 0.6 with gentle bumps (2% of the radius, 3 around a great circle),
    // 327,680 triangles.
    hb::BumpySphereOptions gentle;
    gentle.bump_amplitude = 0.02f;
    gentle.bump_frequency = 3;
    hb::TriangleMesh ellipsoid = hb::make_bumpy_sphere(gentle);
    for (hb::Vec3& p : ellipsoid.positions) p = p.cwiseProduct(hb::Vec3(1.f, 0.75f, 0.6f));
    ellipsoid.compute_vertex_normals();
    save(ellipsoid, "smooth_ellipsoid.off");
  } catch (const std::exception& e) {
    std::cerr << "hb_generate_datasets: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
