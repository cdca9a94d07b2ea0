#include "pieces_option.h"
#include "cli_support.h"
#include "figure_text.h"
#include <iostream>
#ifdef HB_WITH_VTK
#include "polydata_files.h"
#endif

namespace hb::cli {

void add_pieces_options(CLI::App& cmd, std::string& spec, BakeRecipe& recipe) {
  spec = "none";
  cmd.add_option("--pieces", spec, "Pieces: none (one box), auto, faces (a CAD solid's faces), or a piece file (.txt, .ply, .vtp with a PieceId cell array)")
      ->capture_default_str();
  cmd.add_option("--threshold", recipe.pieces.automatic.threshold, "Auto pieces: largest pocket probability of a piece")
      ->check(hb::cli::finite_range(0.0, 1.0))->capture_default_str();
  cmd.add_option("--max-pieces", recipe.pieces.automatic.max_pieces, "Auto pieces: most pieces")
      ->check(CLI::Range(1, 4096))->capture_default_str();
  cmd.add_option("--seam-rings", recipe.seams.rings, "Least rings of seam triangles neighbouring pieces share")
      ->check(CLI::Range(0, 64))->capture_default_str();
  cmd.add_option("--seam-cells", recipe.seams.cells, "Seam overlap width, in position cells of each box")
      ->check(hb::cli::finite_range(0.0, 64.0))->capture_default_str();
}

void apply_pieces_spec(const std::string& spec, BakeRecipe& recipe, const std::vector<std::uint32_t>& face_ids) {
  if (spec == "faces") {
    if (face_ids.empty()) throw UsageError("--pieces faces needs a CAD model (STEP or IGES): this model has no faces");
    recipe.pieces.kind = PiecesRecipe::Kind::given;
    recipe.pieces.given = face_ids;
    return;
  }
#ifdef HB_WITH_VTK
  if (lower_extension(spec) == ".vtp") {  // written by `decompose -o X.vtp`, or edited in ParaView
    recipe.pieces.kind = PiecesRecipe::Kind::given;
    recipe.pieces.given = hb::vtk::read_piece_vtp(spec, 0);
    recipe.pieces.file = spec;  // named in a count mismatch
    return;
  }
#endif
  PiecesRecipe p = pieces_from_spec(spec);
  p.automatic = recipe.pieces.automatic;
  if (p.kind == PiecesRecipe::Kind::automatic) p.automatic.progress = terminal_progress("decomposing");
  recipe.pieces = std::move(p);
}

void print_decomposition(const BakeRecipe& recipe, const BakeResult& result) {
  if (recipe.pieces.kind != PiecesRecipe::Kind::automatic) return;
  std::cerr << "decomposed into " << result.scene.boxes().size() << " pieces in "
            << duration_text(result.decompose_seconds) << "\n";
}

} // namespace hb::cli
