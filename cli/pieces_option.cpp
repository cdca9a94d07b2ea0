#include "pieces_option.h"
#include "cli_support.h"
#include "decomposition/piece_file.h"
#include "decomposition/seam_overlap.h"
#include <chrono>
#include <iostream>

namespace hb::cli {

void add_pieces_options(CLI::App& cmd, PiecesChoice& choice) {
  cmd.add_option("--pieces", choice.spec, "Pieces: none (one box), auto, or a piece file (.txt, .ply)")
      ->capture_default_str();
  cmd.add_option("--threshold", choice.automatic.threshold, "Auto pieces: largest pocket probability of a piece")
      ->check(CLI::Range(0.0, 1.0))->capture_default_str();
  cmd.add_option("--max-pieces", choice.automatic.max_pieces, "Auto pieces: most pieces")
      ->check(CLI::Range(1, 4096))->capture_default_str();
  cmd.add_option("--seam-rings", choice.seams.rings, "Least rings of seam triangles neighbouring pieces share")
      ->check(CLI::Range(0, 64))->capture_default_str();
  cmd.add_option("--seam-cells", choice.seams.cells, "Seam overlap width, in position cells of each box")
      ->check(CLI::Range(0.0, 64.0))->capture_default_str();
}

std::vector<std::uint32_t> resolve_piece_ids(const TriangleMesh& mesh, const PiecesChoice& choice) {
  if (choice.spec == "none" || choice.spec.empty()) return {};
  if (choice.spec != "auto") return read_piece_file(choice.spec, mesh.triangle_count());
  AutoDecompositionOptions options = choice.automatic;
  options.progress = terminal_progress("decomposing");
  const auto start = std::chrono::steady_clock::now();
  const Decomposition d = decompose_auto(mesh, options);
  std::cerr << "decomposed into " << d.piece_count << " pieces in "
            << std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() << " s\n";
  return d.piece_of_triangle;
}

std::vector<std::vector<std::uint32_t>> resolve_pieces(const TriangleMesh& mesh, const PiecesChoice& choice, int m,
                                                       const PositionDensity& density) {
  const std::vector<std::uint32_t> ids = resolve_piece_ids(mesh, choice);
  if (ids.empty()) return piece_triangle_lists(mesh, {});
  SeamOptions seams = choice.seams;
  seams.m = m;
  seams.density = density;
  return piece_triangle_lists(mesh, ids, seams);
}

} // namespace hb::cli
