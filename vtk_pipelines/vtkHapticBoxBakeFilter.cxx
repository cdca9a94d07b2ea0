// 1. convert the surface, read the piece ids if any (hb::bake numbers them compactly; the
//    decomposition filter's, for the recipe's own options, stand for the automatic pieces);
// 2. hb::bake_cached with the recipe, the source and the cache directory, and a progress
//    callback that also honours AbortExecute;
// 3. outputs: the scene, the PBB outlines, the position points and the piece of each
//    triangle for display.
#include "vtkHapticBoxBakeFilter.h"
#include "errors.h"
#include "recipe/box_cache.h"
#include <algorithm>
#include <filesystem>
#include <optional>
#include "vtkHapticBoxSet.h"
#include "vtkHapticBoxUtilities.h"
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkDemandDrivenPipeline.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkIntArray.h>
#include <vtkObjectFactory.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkStringArray.h>

vtkStandardNewMacro(vtkHapticBoxBakeFilter);

vtkHapticBoxBakeFilter::vtkHapticBoxBakeFilter() {
  this->SetNumberOfOutputPorts(4);
  this->SetPieceArrayName("PieceId");
}

vtkHapticBoxBakeFilter::~vtkHapticBoxBakeFilter() {
  this->SetPieceArrayName(nullptr);
  this->SetCacheDirectory(nullptr);
}

void vtkHapticBoxBakeFilter::SetSource(const hb::SourceInfo& source) {
  this->Source = source;
  this->Modified();
}

bool vtkHapticBoxBakeFilter::HasCachedScene() const {
  if (!this->CacheDirectory || !*this->CacheDirectory || this->Source.mesh_hash == 0) return false;
  try {
    std::error_code ec;
    return std::filesystem::is_regular_file(
        hb::BoxCache(this->CacheDirectory).path_for(this->Source.mesh_hash, this->Recipe), ec);
  } catch (const std::exception&) {
    return false;  // e.g. an unreadable piece file: the update reports it
  }
}

void vtkHapticBoxBakeFilter::SetRecipe(const hb::BakeRecipe& recipe) {
  this->Recipe = recipe;
  this->Modified();
}

void vtkHapticBoxBakeFilter::SetM(int m) {
  m = std::clamp(m, 2, 1024);
  if (m == this->Recipe.options.params.m) return;
  this->Recipe.options.params.m = m;
  this->Modified();
}

void vtkHapticBoxBakeFilter::SetN(int n) {
  n = std::clamp(n, 2, 256);
  if (n == this->Recipe.options.params.n) return;
  this->Recipe.options.params.n = n;
  this->Modified();
}

void vtkHapticBoxBakeFilter::SetPadding(double padding) {
  const float p = float(std::clamp(padding, 0.0, 1.0));
  if (p == this->Recipe.options.obb.padding) return;
  this->Recipe.options.obb.padding = p;
  this->Modified();
}

void vtkHapticBoxBakeFilter::SetRefine(bool refine) {
  if (refine == this->Recipe.options.refine) return;
  this->Recipe.options.refine = refine;
  this->Modified();
}

vtkHapticBoxSet* vtkHapticBoxBakeFilter::GetBoxSet() {
  return vtkHapticBoxSet::SafeDownCast(this->GetOutputDataObject(0));
}

int vtkHapticBoxBakeFilter::FillOutputPortInformation(int port, vtkInformation* info) {
  info->Set(vtkDataObject::DATA_TYPE_NAME(), port == 0 ? "vtkHapticBoxSet" : "vtkPolyData");
  return 1;
}

vtkTypeBool vtkHapticBoxBakeFilter::ProcessRequest(vtkInformation* request, vtkInformationVector** inputVector,
                                                   vtkInformationVector* outputVector) {
  // vtkDataObjectTypes cannot make a vtkHapticBoxSet: create the outputs here.
  if (request->Has(vtkDemandDrivenPipeline::REQUEST_DATA_OBJECT())) {
    for (int port = 0; port < this->GetNumberOfOutputPorts(); ++port) {
      vtkInformation* info = outputVector->GetInformationObject(port);
      vtkDataObject* current = info->Get(vtkDataObject::DATA_OBJECT());
      if (port == 0 && !vtkHapticBoxSet::SafeDownCast(current)) {
        vtkNew<vtkHapticBoxSet> set;
        info->Set(vtkDataObject::DATA_OBJECT(), set);
      } else if (port > 0 && !vtkPolyData::SafeDownCast(current)) {
        vtkNew<vtkPolyData> pd;
        info->Set(vtkDataObject::DATA_OBJECT(), pd);
      }
    }
    return 1;
  }
  return this->Superclass::ProcessRequest(request, inputVector, outputVector);
}

int vtkHapticBoxBakeFilter::RequestData(vtkInformation*, vtkInformationVector** inputVector,
                                        vtkInformationVector* outputVector) {
  this->LastError.clear();
  this->CachePath.clear();
  this->CacheWarning.clear();
  this->FromCache = false;
  this->BakeSeconds = 0.0;
  try {
    vtkPolyData* input = vtkPolyData::GetData(inputVector[0], 0);
    vtkHapticBoxSet* boxes = vtkHapticBoxSet::GetData(outputVector, 0);
    vtkPolyData* outlines = vtkPolyData::GetData(outputVector, 1);
    vtkPolyData* positions = vtkPolyData::GetData(outputVector, 2);
    vtkPolyData* pieces = vtkPolyData::GetData(outputVector, 3);
    this->UpdateProgress(0.0);
    const hb::TriangleMesh mesh = vtkHapticBoxUtilities::ToTriangleMesh(input);

    hb::BakeRecipe recipe = this->Recipe;
    // Piece ids: only meaningful when no triangle was dropped or split by the conversion.
    vtkDataArray* ids = (this->PieceArrayName && input->GetCellData())
        ? input->GetCellData()->GetArray(this->PieceArrayName) : nullptr;
    if (ids) {
      if (ids->GetNumberOfTuples() != vtkIdType(mesh.triangle_count()) || input->GetNumberOfStrips() > 0 ||
          input->GetNumberOfPolys() != vtkIdType(mesh.triangle_count()))
        throw hb::InvalidInput(std::string("the cell array ") + this->PieceArrayName +
                               " needs a surface of triangles only (one id per triangle)");
      std::vector<std::uint32_t> values(mesh.triangle_count());
      for (vtkIdType c = 0; c < ids->GetNumberOfTuples(); ++c) {
        const double v = ids->GetComponent(c, 0);
        if (!(v >= 0.0 && v < 4294967296.0))
          throw hb::InvalidInput(std::string("the cell array ") + this->PieceArrayName + " holds " +
                                 std::to_string(v) + " (piece ids are integers >= 0)");
        values[std::size_t(c)] = std::uint32_t(v);
      }
      // The decomposition filter's pieces for the recipe's own options are the recipe's
      // automatic pieces (same key, no second decomposition); any other ids are given ones.
      auto* made = vtkStringArray::SafeDownCast(input->GetFieldData()->GetAbstractArray("DecompositionOptions"));
      const bool same = made && made->GetNumberOfValues() == 1 &&
                        recipe.pieces.kind == hb::PiecesRecipe::Kind::automatic &&
                        made->GetValue(0) == vtkHapticBoxUtilities::DecompositionSignature(recipe.pieces.automatic);
      if (same) {
        recipe.pieces.resolved = std::move(values);
      } else {
        recipe.pieces.kind = hb::PiecesRecipe::Kind::given;
        recipe.pieces.given = std::move(values);
      }
    }
    const bool decompose = recipe.pieces.kind == hb::PiecesRecipe::Kind::automatic && recipe.pieces.resolved.empty();
    if (decompose) recipe.pieces.automatic.progress = vtkHapticBoxUtilities::MakeProgressCallback(this, 0.02, 0.3);
    recipe.options.progress = vtkHapticBoxUtilities::MakeProgressCallback(this, decompose ? 0.3 : 0.02, 0.98);
    hb::SourceInfo source = this->Source;
    if (source.triangles == 0) source.triangles = mesh.triangle_count();
    if (!(source.diagonal > 0.f)) source.diagonal = mesh.bounds().diagonal();
    std::optional<hb::BoxCache> cache;
    if (this->CacheDirectory && *this->CacheDirectory) cache.emplace(this->CacheDirectory);
    hb::CachedBake baked;
    if (this->CacheOnly) {
      std::optional<hb::BoxScene> cached = (cache && source.mesh_hash != 0)
          ? cache->load(source.mesh_hash, recipe) : std::nullopt;
      if (!cached) throw hb::InvalidInput("no cached scene for " + source.mesh_path + " and this recipe" +
                                          (cache ? " in " + cache->dir() : std::string(" (no cache directory)")));
      baked.result.scene = std::move(*cached);
      baked.from_cache = true;
      baked.path = cache->path_for(source.mesh_hash, recipe);
    } else {
      baked = hb::bake_cached(mesh, recipe, source, cache ? &*cache : nullptr);
    }
    this->CachePath = baked.path;
    this->CacheWarning = baked.warning;
    this->FromCache = baked.from_cache;
    const hb::BakeStats stats = baked.result.stats;
    auto scene = std::make_shared<const hb::BoxScene>(std::move(baked.result.scene));
    this->BakeSeconds = stats.seconds;
    boxes->SetScene(scene);

    outlines->ShallowCopy(vtkHapticBoxUtilities::BoxOutlines(*scene));
    // Position points with their box and face.
    vtkNew<vtkPoints> pts;
    vtkNew<vtkCellArray> verts;
    vtkNew<vtkIntArray> ptBox, ptFace;
    ptBox->SetName("BoxId");
    ptFace->SetName("Face");
    for (std::size_t b = 0; b < scene->parts().boxes.size(); ++b) {
      const hb::HapticBox& box = scene->parts().boxes[b];
      const int m = box.params().m;
      for (int face = 0; face < 6; ++face)
        for (int i = 0; i < m; ++i)
          for (int j = 0; j < m; ++j) {
            const hb::Vec3 p = box.layout().position_point(face, i, j);
            const vtkIdType id = pts->InsertNextPoint(p.x(), p.y(), p.z());
            verts->InsertNextCell(1, &id);
            ptBox->InsertNextValue(int(b));
            ptFace->InsertNextValue(face);
          }
    }
    vtkNew<vtkDoubleArray> seconds, bytes, fromCache;
    seconds->SetName("BakeSeconds");
    seconds->InsertNextValue(stats.seconds);
    bytes->SetName("TableBytes");
    bytes->InsertNextValue(double(scene->bytes().tables));
    fromCache->SetName("FromCache");
    fromCache->InsertNextValue(baked.from_cache ? 1.0 : 0.0);
    outlines->GetFieldData()->AddArray(seconds);
    outlines->GetFieldData()->AddArray(bytes);
    outlines->GetFieldData()->AddArray(fromCache);
    positions->SetPoints(pts);
    positions->SetVerts(verts);
    positions->GetPointData()->AddArray(ptBox);
    positions->GetPointData()->AddArray(ptFace);

    // The piece of each triangle, as the scene (and so its .hbox file) records it.
    pieces->ShallowCopy(input);
    vtkNew<vtkIntArray> pieceIds;
    pieceIds->SetName("PieceId");
    pieceIds->SetNumberOfValues(vtkIdType(mesh.triangle_count()));
    const std::vector<std::uint32_t>& of = scene->parts().piece_of_triangle;
    for (std::size_t t = 0; t < mesh.triangle_count(); ++t)
      pieceIds->SetValue(vtkIdType(t), t < of.size() ? int(of[t]) : 0);
    // (the output's own attributes: the input's arrays stay as they were)
    if (input->GetNumberOfCells() == vtkIdType(mesh.triangle_count())) pieces->GetCellData()->AddArray(pieceIds);
    this->UpdateProgress(1.0);
    return 1;
  } catch (const std::exception& e) {
    this->LastError = e.what();
    vtkErrorMacro(<< e.what());
    return 0;
  }
}

void vtkHapticBoxBakeFilter::PrintSelf(ostream& os, vtkIndent indent) {
  this->Superclass::PrintSelf(os, indent);
  os << indent << "M: " << this->GetM() << "\n"
     << indent << "N: " << this->GetN() << "\n"
     << indent << "Padding: " << this->GetPadding() << "\n"
     << indent << "Refine: " << this->GetRefine() << "\n"
     << indent << "Pieces: " << hb::pieces_spec(this->Recipe.pieces) << "\n"
     << indent << "PieceArrayName: " << (this->PieceArrayName ? this->PieceArrayName : "(none)") << "\n"
     << indent << "CacheDirectory: " << (this->CacheDirectory ? this->CacheDirectory : "(none)") << "\n";
}
