#include "pieces_option.h"
#include "cli_support.h"
#include "figure_text.h"
#include <iostream>
#ifdef HB_WITH_VTK
#include "polydata_files.h"
#endif

namespace hb::cli {

void PiecesArgs::apply_tuning(BakeRecipe& recipe) const {
  if (threshold) recipe.pieces.automatic.threshold = *threshold;
  if (max_pieces) recipe.pieces.automatic.max_pieces = *max_pieces;
  if (seam_rings) recipe.seams.rings = *seam_rings;
  if (seam_cells) recipe.seams.cells = *seam_cells;
  if (padding) recipe.options.obb.padding = *padding;
}

void add_pieces_options(CLI::App& cmd, PiecesArgs& args, const std::string& default_kind, const BakeRecipe& defaults,
                        const BakeRecipe* other) {
  // "0.001" or, when the other recipe differs, "0.001 for the default bake, 0.004 for one sampling".
  const auto shown = [&](auto field) {
    const std::string mine = spec_format(double(field(defaults)));
    if (!other || spec_format(double(field(*other))) == mine) return mine;
    return mine + " for the default bake, " + spec_format(double(field(*other))) + " for one sampling";
  };
  cmd.add_option_function<std::string>(
         "--pieces",
         [&args](const std::string& spec) {
           const auto number = [](auto& field, double lo, double hi) {
             return [&field, lo, hi](const std::string& v, const std::string& what) {
               field = spec_number_or_usage(v, what, lo, hi);
             };
           };
           const auto whole = [](std::optional<int>& field, int lo, int hi) {
             return [&field, lo, hi](const std::string& v, const std::string& what) {
               const double x = spec_number_or_usage(v, what, lo, hi);
               if (x != double(int(x))) throw UsageError(what + ": '" + v + "' is not a whole number");
               field = int(x);
             };
           };
           std::string kind = args.spec;
           parse_spec("--pieces", spec,
                      {{"threshold", number(args.threshold, 0.0, 1.0)},
                       {"max", whole(args.max_pieces, 1, 4096)},
                       {"seam-rings", whole(args.seam_rings, 0, 64)},
                       {"seam-cells", number(args.seam_cells, 0.0, 64.0)},
                       {"padding", number(args.padding, 0.0, 1.0)}},
                      &kind);
           args.spec = kind;
           args.given = true;
         },
         "How the mesh is cut into boxes: none (one box), auto, faces (a CAD solid's faces) or a piece file (.txt, "
         ".ply, .vtp with a PieceId cell array) (default " + default_kind + "); then any of threshold=T (auto: "
         "largest pocket probability of a piece; default " +
             shown([](const BakeRecipe& r) { return r.pieces.automatic.threshold; }) +
         "), max=N (auto: most pieces; default " + shown([](const BakeRecipe& r) { return r.pieces.automatic.max_pieces; }) +
         "), seam-rings=R (least rings of seam triangles neighbouring pieces share; default " +
         shown([](const BakeRecipe& r) { return r.seams.rings; }) + "), seam-cells=C (seam overlap, position cells; default " +
         shown([](const BakeRecipe& r) { return r.seams.cells; }) +
         "), padding=P (each box's PBB padding, fraction of its diagonal; default " +
         shown([](const BakeRecipe& r) { return r.options.obb.padding; }) + ")")
      ->type_name("KIND[,KEY=VALUE...]");
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
  if (p.kind == PiecesRecipe::Kind::automatic) {
    p.automatic.progress = terminal_progress("decomposing");
    p.automatic.on_phase = decompose_times();
  }
  recipe.pieces = std::move(p);
}

void print_decomposition(const BakeRecipe& recipe, const BakeResult& result) {
  if (recipe.pieces.kind != PiecesRecipe::Kind::automatic) return;
  std::cerr << "decomposed into " << result.scene.parts().boxes.size() << " pieces in "
            << duration_text(result.decompose_seconds) << "\n";
}

} // namespace hb::cli
