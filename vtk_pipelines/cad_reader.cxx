// CAD to triangles:
//  1. STEPControl_Reader / IGESControl_Reader read the file and transfer every root into one
//     shape, in millimetres (xstep.cascade.unit); OpenCASCADE's console messages are muted so
//     that they never mix into the command's output. Before that, the file is held to its
//     format (formats/step_check.h, iges_global.h, iges_check.h), a STEP file whose reader
//     recorded a damaged instance is refused before the translator, and a shape whose edges
//     miss their faces by more than 5% of its size is refused before the mesher.
//  2. The chordal deviation follows the force budget: d = force_tolerance / stiffness, clamped
//     to [1e-4, 1e-2] x the bounding-box diagonal (CadOptions), unless given in mm.
//  3. BRepMesh_IncrementalMesh tessellates every face, finer in rounds until the measured
//     deviation is within the one asked for (at most 5 rounds, kRefineSeconds, and no round
//     once a finer mesh stops helping: a warning says why); each face's triangles are collected with
//     the face's orientation, and nodes at the same position (the shared edges, which BRepMesh
//     discretises once for both faces) are merged, so a closed solid gives a closed mesh.
#include "cad_reader.h"
#include "string_util.h"
#include "errors.h"
#include "formats/iges_check.h"
#include "formats/iges_global.h"
#include "formats/step_check.h"
#include <BRepAdaptor_Surface.hxx>
#include <BRep_Builder.hxx>
#include <TopoDS_Compound.hxx>
#include <BRepBndLib.hxx>
#include <BRepBuilderAPI_MakeVertex.hxx>
#include <BRepMesh_IncrementalMesh.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <BRepPrimAPI_MakeSphere.hxx>
#include <BRep_Tool.hxx>
#include <BRepTools.hxx>
#include <Geom_Surface.hxx>
#include <ShapeAnalysis_Surface.hxx>
#include <Bnd_Box.hxx>
#include <IGESControl_Controller.hxx>
#include <IGESControl_Reader.hxx>
#include <IGESControl_Writer.hxx>
#include <BRepBuilderAPI_NurbsConvert.hxx>
#include <IGESData_IGESEntity.hxx>
#include <IGESData_IGESModel.hxx>
#include <Interface_Check.hxx>
#include <Interface_InterfaceModel.hxx>
#include <TCollection_HAsciiString.hxx>
#include <StepShape_FaceSurface.hxx>
#include <Interface_Static.hxx>
#include <Message.hxx>
#include <Message_Messenger.hxx>
#include <Message_PrinterOStream.hxx>
#include <Poly_Triangulation.hxx>
#include <STEPControl_Reader.hxx>
#include <STEPControl_Writer.hxx>
#include <Standard_Failure.hxx>
#include <TColStd_SequenceOfAsciiString.hxx>
#include <TopExp.hxx>
#include <TopExp_Explorer.hxx>
#include <TopLoc_Location.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Face.hxx>
#include <TopoDS_Shape.hxx>
#include <gp_Ax2.hxx>
#include <gp_Pnt2d.hxx>
#include <algorithm>
#include <chrono>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <mutex>
#include <unordered_map>

namespace hb::vtk {

// The time the mesher may spend refining toward the chordal deviation asked for, s.
constexpr double kRefineSeconds = 5.0;

namespace {

namespace fs = std::filesystem;

void mute_opencascade() {
  static std::once_flag once;
  std::call_once(once, [] {
    const Handle(Message_Messenger)& messenger = Message::DefaultMessenger();
    messenger->RemovePrinters(STANDARD_TYPE(Message_PrinterOStream));
    Interface_Static::SetCVal("xstep.cascade.unit", "MM");
    Interface_Static::SetCVal("write.step.unit", "MM");
  });
}

const char* surface_type_name(GeomAbs_SurfaceType t) {
  switch (t) {
    case GeomAbs_Plane: return "plane";
    case GeomAbs_Cylinder: return "cylinder";
    case GeomAbs_Cone: return "cone";
    case GeomAbs_Sphere: return "sphere";
    case GeomAbs_Torus: return "torus";
    case GeomAbs_BezierSurface: return "bezier";
    case GeomAbs_BSplineSurface: return "bspline";
    case GeomAbs_SurfaceOfRevolution: return "revolution";
    case GeomAbs_SurfaceOfExtrusion: return "extrusion";
    case GeomAbs_OffsetSurface: return "offset";
    default: return "other";
  }
}

// OpenCASCADE's reader records what it could not read (a syntax error, a parameter of the
// wrong type or count, a reference to an instance that failed) and goes on; its translator
// then follows what was left unset and crashes. Such a file is refused, naming the first fault.
void refuse_read_failures(const std::string& path, const char* format, const Handle(Interface_InterfaceModel)& model) {
  if (model.IsNull()) return;
  auto text = [](const char* s) {
    std::string t = s ? s : "";
    while (!t.empty() && std::isspace((unsigned char)t.back())) t.pop_back();
    return t.empty() ? std::string("a parameter could not be read") : t;
  };
  const Handle(Interface_Check)& global = model->GlobalCheck(Standard_True);
  if (!global.IsNull() && global->NbFails() > 0)
    throw InvalidInput(path + ": the " + format + " file is damaged: " + text(global->CFail(1)));
  for (int i = 1; i <= model->NbEntities(); ++i) {
    if (!model->IsErrorEntity(i)) continue;
    const Handle(Interface_Check)& check = model->Check(i, Standard_True);
    if (check.IsNull() || check->NbFails() == 0) continue;
    const Handle(Standard_Transient)& entity = model->Value(i);
    const Handle(TCollection_HAsciiString) label = entity.IsNull() ? nullptr : model->StringLabel(entity);
    throw InvalidInput(path + ": the " + format + " file is damaged at instance " +
                       (label.IsNull() ? std::to_string(i) : std::string(label->ToCString())) + ": " + text(check->CFail(1)));
  }
}

// Reads and transfers the file; `file_faces` is the number of faces the file defines (STEP
// face surfaces; IGES faces, else trimmed and bounded surfaces), to be held against the faces
// the transfer produced: OpenCASCADE drops a face it cannot translate without failing.
TopoDS_Shape read_shape(const std::string& path, bool step, nlohmann::json& facts, int& file_faces) {
  file_faces = 0;
  if (step) {
    {
      // A reference to a missing instance crashed OpenCASCADE's translator.
      std::ifstream in(path, std::ios::binary);
      check_step_references(path, std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>()));
    }
    STEPControl_Reader reader;
    if (reader.ReadFile(path.c_str()) != IFSelect_RetDone) throw InvalidInput(path + ": not a readable STEP file");
    const Handle(Interface_InterfaceModel) model = reader.Model();
    refuse_read_failures(path, "STEP", model);
    if (!model.IsNull())
      for (int i = 1; i <= model->NbEntities(); ++i)
        if (!model->Value(i).IsNull() && model->Value(i)->IsKind(STANDARD_TYPE(StepShape_FaceSurface))) ++file_faces;
    TColStd_SequenceOfAsciiString lengths, angles, solid_angles;
    reader.FileUnits(lengths, angles, solid_angles);
    if (lengths.Length() > 0) facts["file_unit"] = lengths.Value(1).ToCString();
    if (reader.TransferRoots() == 0) throw InvalidInput(path + ": the STEP file holds no shape OpenCASCADE can transfer");
    return reader.OneShape();
  }
  {
    // OpenCASCADE takes inches when the global section does not parse, and the unit flag over
    // the unit name: either rescales the model silently. The section is held to itself first.
    std::ifstream in(path, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    facts["file_mm_per_unit"] = iges_mm_per_unit(path, bytes);
    // Its translator trusts the directory's pointers and the counts in the parameter data: a
    // damaged one was a segmentation fault.
    check_iges_structure(path, bytes);
  }
  IGESControl_Reader reader;
  if (reader.ReadFile(path.c_str()) != IFSelect_RetDone) throw InvalidInput(path + ": not a readable IGES file");
  const Handle(IGESData_IGESModel) model = reader.IGESModel();
  if (!model.IsNull()) {
    int faces = 0, surfaces = 0;
    for (int i = 1; i <= model->NbEntities(); ++i) {
      const Handle(IGESData_IGESEntity) e = model->Entity(i);
      if (e.IsNull()) continue;
      if (e->TypeNumber() == 510) ++faces;
      if (e->TypeNumber() == 144 || e->TypeNumber() == 143) ++surfaces;
    }
    file_faces = faces > 0 ? faces : surfaces;
    facts["file_unit"] = model->GlobalSection().UnitName().IsNull() ? "" : model->GlobalSection().UnitName()->ToCString();
  }
  if (reader.TransferRoots() == 0) throw InvalidInput(path + ": the IGES file holds no shape OpenCASCADE can transfer");
  return reader.OneShape();
}

struct PointKey {
  float x, y, z;
  bool operator==(const PointKey& o) const { return x == o.x && y == o.y && z == o.z; }
};
struct PointHash {
  std::size_t operator()(const PointKey& p) const {
    std::uint32_t a, b, c;
    std::memcpy(&a, &p.x, 4);
    std::memcpy(&b, &p.y, 4);
    std::memcpy(&c, &p.z, 4);
    return (std::size_t(a) * 73856093u) ^ (std::size_t(b) * 19349663u) ^ (std::size_t(c) * 83492791u);
  }
};

// How far the chords stray from the exact surface: each sampled triangle's centroid and edge
// midpoints projected onto the face's surface (ShapeAnalysis_Surface: closed forms for planes,
// cylinders, spheres..., a projection otherwise), the largest gap. Planes give 0.
double measure_deviation(const TopTools_IndexedMapOfShape& faces) {
  std::size_t total = 0;
  for (int fi = 1; fi <= faces.Extent(); ++fi) {
    TopLoc_Location loc;
    const Handle(Poly_Triangulation)& tri = BRep_Tool::Triangulation(TopoDS::Face(faces(fi)), loc);
    if (!tri.IsNull()) total += std::size_t(tri->NbTriangles());
  }
  const int stride = int(std::max<std::size_t>(1, total / 20000));
  double worst = 0.0;
  for (int fi = 1; fi <= faces.Extent(); ++fi) {
    const TopoDS_Face& face = TopoDS::Face(faces(fi));
    TopLoc_Location tri_loc;
    const Handle(Poly_Triangulation)& tri = BRep_Tool::Triangulation(face, tri_loc);
    if (tri.IsNull()) continue;
    const Handle(Geom_Surface) surface = BRep_Tool::Surface(face);  // located in the model
    if (surface.IsNull()) continue;
    ShapeAnalysis_Surface analysis(surface);
    const gp_Trsf trsf = tri_loc.Transformation();
    const bool uv = tri->HasUVNodes();
    for (int t = 1; t <= tri->NbTriangles(); t += stride) {
      int n[3];
      tri->Triangle(t).Get(n[0], n[1], n[2]);
      gp_XYZ p[3];
      for (int k = 0; k < 3; ++k) p[k] = tri->Node(n[k]).Transformed(trsf).XYZ();
      const gp_XYZ q[4] = {(p[0] + p[1] + p[2]) / 3.0, (p[0] + p[1]) / 2.0, (p[1] + p[2]) / 2.0, (p[0] + p[2]) / 2.0};
      if (uv) {
        // The nodes' parameters give the projection its start: a local search, not a global
        // one (a global projection onto a B-spline surface costs milliseconds a point).
        gp_XY w[3];
        for (int k = 0; k < 3; ++k) w[k] = tri->UVNode(n[k]).XY();
        const gp_XY start[4] = {(w[0] + w[1] + w[2]) / 3.0, (w[0] + w[1]) / 2.0, (w[1] + w[2]) / 2.0, (w[0] + w[2]) / 2.0};
        for (int k = 0; k < 4; ++k) {
          analysis.NextValueOfUV(gp_Pnt2d(start[k]), gp_Pnt(q[k]), 1e-7);
          worst = std::max(worst, analysis.Gap());
        }
      } else {
        for (const gp_XYZ& x : q) {
          analysis.ValueOfUV(gp_Pnt(x), 1e-7);
          worst = std::max(worst, analysis.Gap());
        }
      }
    }
  }
  return worst;
}

// Edges and vertices that miss their faces: the transfer widens their tolerance until they
// meet (a damaged direction tilted a cylinder, a moved control point bent an edge), and
// BRepMesh then meshed for minutes (823 MB after 120 s) or failed after a minute. Valid files
// stay far below: 1e-9 to 1.3e-2 of the diagonal (OpenCASCADE's sample models, the reference
// solid); the damaged ones measured 0.07 and 0.13.
void refuse_stray_edges(const std::string& path, const TopoDS_Shape& shape, double diagonal) {
  double worst = 0.0;
  for (TopExp_Explorer e(shape, TopAbs_VERTEX); e.More(); e.Next()) worst = std::max(worst, BRep_Tool::Tolerance(TopoDS::Vertex(e.Current())));
  for (TopExp_Explorer e(shape, TopAbs_EDGE); e.More(); e.Next()) worst = std::max(worst, BRep_Tool::Tolerance(TopoDS::Edge(e.Current())));
  constexpr double kMostOfDiagonal = 0.05;
  if (worst > kMostOfDiagonal * diagonal)
    throw InvalidInput(path + ": its edges miss their faces by up to " + std::to_string(worst) + " mm (" +
                       std::to_string(int(std::lround(100.0 * worst / diagonal))) + "% of the model's " + std::to_string(diagonal) +
                       " mm diagonal; OpenCASCADE widened their tolerance to join them): the geometry is damaged, and meshing it "
                       "would not end");
}

// How BRepMesh met the chordal deviation asked for: the deflection asked last, the deviation
// measured, and when it is above the one asked for, why the refinement stopped short.
struct Refinement {
  double deflection = 0.0, measured = 0.0;
  std::string short_because;
};

// BRepMesh's deflection is a target, not a bound: mesh, measure, and mesh finer until the
// measured deviation is within `deviation` (at most 5 rounds, each at most 10x finer, none
// once a round stopped helping or would take the whole past kRefineSeconds).
Refinement mesh_to_deviation(const TopoDS_Shape& shape, const TopTools_IndexedMapOfShape& faces, double deviation, double angular_rad,
                             const std::string& path) {
  Refinement r;
  double deflection_asked = deviation, previous_deflection = deviation, round_s = 0.0;
  const auto start = std::chrono::steady_clock::now();
  r.short_because = "after 5 rounds";
  for (int round = 0; round < 5; ++round) {
    // A round costs about the triangles it makes, which grow as the deflection shrinks: no
    // round that would take the whole beyond kRefineSeconds (a damaged surface, far from its
    // edges, kept refining for a minute).
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (round > 0 && elapsed + round_s * previous_deflection / deflection_asked > kRefineSeconds) {
      r.short_because = "(a finer mesh would take more than " + std::to_string(int(kRefineSeconds)) +
                        " s: the surfaces are far from their edges, a damaged file?)";
      break;
    }
    const auto round_start = std::chrono::steady_clock::now();
    if (round > 0) BRepTools::Clean(shape);
    BRepMesh_IncrementalMesh mesher(shape, deflection_asked, Standard_False, angular_rad, Standard_True);
    if (!mesher.IsDone()) throw InvalidInput(path + ": OpenCASCADE could not tessellate the shape");
    const double before = r.measured;
    r.measured = measure_deviation(faces);
    r.deflection = deflection_asked;
    round_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - round_start).count();
    previous_deflection = deflection_asked;
    if (r.measured <= deviation) break;
    // A gap that a finer mesh does not close is not the chords' but the edges' (off their
    // surface by up to their tolerance): refining on multiplies the triangles (a plane moved
    // 1 mm off its edges in a STEP file cost 3 GB and more than 120 s).
    if (round > 0 && r.measured > 0.95 * before) {
      r.short_because = "(a finer mesh did not bring it closer: edges off their surface)";
      break;
    }
    // At most 10x finer a round: a gap far above the deflection is the edges' too.
    deflection_asked *= std::max(0.1, 0.9 * deviation / r.measured);
  }
  return r;
}

} // namespace


CadModel read_cad(const std::string& path, const CadOptions& options) {
  if (!fs::exists(path)) throw IoError(path + ": no such file");
  if (!std::ifstream(path).good()) throw IoError(path + ": cannot open the file");
  if (fs::file_size(path) == 0) throw IoError(path + ": the file is empty");
  if (!(options.force_tolerance_n > 0)) throw InvalidInput(path + ": the force tolerance must be > 0");
  mute_opencascade();
  const std::string p = lower(path);
  const bool step = p.size() > 4 && (p.substr(p.size() - 4) == ".stp" || p.substr(p.size() - 5) == ".step");
  CadModel model;
  model.format = step ? "STEP" : "IGES";
  nlohmann::json& f = model.facts;
  try {
    int file_faces = 0;
    const TopoDS_Shape shape = read_shape(path, step, f, file_faces);
    if (shape.IsNull()) throw InvalidInput(path + ": no shape in the file");
    TopTools_IndexedMapOfShape solids, shells, faces, edges;
    TopExp::MapShapes(shape, TopAbs_SOLID, solids);
    TopExp::MapShapes(shape, TopAbs_SHELL, shells);
    TopExp::MapShapes(shape, TopAbs_FACE, faces);
    TopExp::MapShapes(shape, TopAbs_EDGE, edges);
    if (faces.Extent() == 0)
      throw InvalidInput(path + ": no solid (and no surface) in the file: nothing to touch (" + std::to_string(edges.Extent()) +
                         " edges, " + std::to_string(solids.Extent()) + " solids)");
    if (solids.Extent() == 0)
      model.warnings.push_back(path + ": no solid, only " + std::to_string(faces.Extent()) +
                               " free faces: the surface may be open (contacts need a closed surface)");
    f["solids"] = solids.Extent();
    f["shells"] = shells.Extent();
    f["faces"] = faces.Extent();
    f["edges"] = edges.Extent();
    std::map<std::string, int> types;
    for (int i = 1; i <= faces.Extent(); ++i) ++types[surface_type_name(BRepAdaptor_Surface(TopoDS::Face(faces(i))).GetType())];
    f["face_types"] = types;

    Bnd_Box box;
    BRepBndLib::Add(shape, box);
    if (box.IsVoid()) throw InvalidInput(path + ": the shape has no extent");
    double x0, y0, z0, x1, y1, z1;
    box.Get(x0, y0, z0, x1, y1, z1);
    const double diagonal = std::sqrt((x1 - x0) * (x1 - x0) + (y1 - y0) * (y1 - y0) + (z1 - z0) * (z1 - z0));
    if (!std::isfinite(diagonal) || diagonal > 1e7 || !(diagonal > 1e-6))
      throw InvalidInput(path + ": absurd size: bounding-box diagonal " + std::to_string(diagonal) + " mm");
    f["bounding_box_mm"] = {{x0, y0, z0}, {x1, y1, z1}};
    refuse_stray_edges(path, shape, diagonal);
    double deviation = options.chordal_deviation_mm;
    if (deviation > 0) {
      f["chordal_deviation_source"] = "--chordal-mm";
    } else {
      // The solid (in mm) at the scale it is felt at: F / k at the device, in model mm.
      const hb::Workspace ws = hb::make_workspace(diagonal, options.workspace);
      const double budget = options.force_tolerance_n / ws.stiffness_n_per_m / ws.metres_per_unit;
      deviation = std::clamp(budget, 1e-4 * diagonal, 1e-2 * diagonal);
      f["chordal_deviation_source"] = "force budget: " + std::to_string(options.force_tolerance_n) + " N / " +
                                      std::to_string(ws.stiffness_n_per_m) + " N/m at the device (" + ws.describe() +
                                      ") = " + std::to_string(budget) + " mm, clamped to [1e-4, 1e-2] x diagonal";
    }
    if (deviation < 1e-5 * diagonal)
      throw InvalidInput(path + ": chordal deviation " + std::to_string(deviation) + " mm is below 1e-5 x the diagonal (" +
                         std::to_string(diagonal) + " mm): far more triangles than a haptic model needs");
    f["chordal_deviation_mm"] = deviation;
    const Refinement r = mesh_to_deviation(shape, faces, deviation, options.angular_deviation_deg * M_PI / 180.0, path);
    f["mesher_deflection_mm"] = r.deflection;
    f["measured_deviation_mm"] = r.measured;
    if (r.measured > deviation)
      model.warnings.push_back(path + ": measured chordal deviation " + std::to_string(r.measured) + " mm exceeds the " +
                               std::to_string(deviation) + " mm asked for " + r.short_because);

    std::unordered_map<PointKey, std::uint32_t, PointHash> index;
    double deflection = 0.0;
    int untessellated = 0;
    for (int fi = 1; fi <= faces.Extent(); ++fi) {
      const TopoDS_Face& face = TopoDS::Face(faces(fi));
      TopLoc_Location loc;
      const Handle(Poly_Triangulation)& tri = BRep_Tool::Triangulation(face, loc);
      if (tri.IsNull() || tri->NbTriangles() == 0) {
        ++untessellated;
        continue;
      }
      deflection = std::max(deflection, tri->Deflection());
      const gp_Trsf trsf = loc.Transformation();
      std::vector<std::uint32_t> ids(std::size_t(tri->NbNodes()) + 1);
      for (int n = 1; n <= tri->NbNodes(); ++n) {
        const gp_Pnt q = tri->Node(n).Transformed(trsf);
        const PointKey key{float(q.X()), float(q.Y()), float(q.Z())};
        auto [it, added] = index.emplace(key, std::uint32_t(model.mesh.positions.size()));
        if (added) model.mesh.positions.emplace_back(key.x, key.y, key.z);
        ids[std::size_t(n)] = it->second;
      }
      const bool reversed = face.Orientation() == TopAbs_REVERSED;
      for (int t = 1; t <= tri->NbTriangles(); ++t) {
        int a, b, c;
        tri->Triangle(t).Get(a, b, c);
        if (reversed) std::swap(b, c);
        const Triangle triangle{ids[std::size_t(a)], ids[std::size_t(b)], ids[std::size_t(c)]};
        if (triangle[0] == triangle[1] || triangle[1] == triangle[2] || triangle[0] == triangle[2]) continue;
        model.mesh.triangles.push_back(triangle);
        model.face_ids.push_back(std::uint32_t(fi - 1));
      }
    }
    // Faces lost: those the transfer dropped and those the mesher gave no triangle.
    const int dropped = std::max(0, file_faces - faces.Extent());
    const int total = std::max(file_faces, faces.Extent());
    f["faces_in_file"] = file_faces;
    if (dropped + untessellated > 0) {
      std::string what = path + ": " + std::to_string(dropped + untessellated) + " of " + std::to_string(total) + " faces lost (" +
                         std::to_string(dropped) + " failed to translate, " + std::to_string(untessellated) + " gave no triangles)";
      if (!options.accept_lost_faces)
        throw InvalidInput(what + ": the model would have holes; give --cad accept-lost-faces to keep the rest");
      model.warnings.push_back(what + ", kept with --cad accept-lost-faces");
      f["faces_lost"] = dropped + untessellated;
    }
    if (model.mesh.triangles.empty()) throw InvalidInput(path + ": the tessellation has no triangles");
    f["tessellation_deflection_mm"] = deflection;
  } catch (const Standard_Failure& e) {
    throw InvalidInput(path + ": OpenCASCADE: " + std::string(e.GetMessageString() ? e.GetMessageString() : "failure"));
  }
  model.mesh.compute_vertex_normals();
  f["triangles"] = model.mesh.triangle_count();
  f["file_unit_converted_to"] = "mm";
  return model;
}

void write_reference_solid_step(const std::string& path, double radius_mm, double height_mm) {
  mute_opencascade();
  const TopoDS_Shape cylinder = BRepPrimAPI_MakeCylinder(radius_mm, height_mm).Shape();
  const TopoDS_Shape sphere = BRepPrimAPI_MakeSphere(gp_Pnt(3.0 * radius_mm, 0, 0.5 * height_mm), radius_mm).Shape();
  TopoDS_Compound both;
  BRep_Builder builder;
  builder.MakeCompound(both);
  builder.Add(both, cylinder);
  builder.Add(both, sphere);
  STEPControl_Writer writer;
  if (writer.Transfer(both, STEPControl_AsIs) != IFSelect_RetDone || writer.Write(path.c_str()) != IFSelect_RetDone)
    throw IoError(path + ": OpenCASCADE could not write the STEP file");
}

void write_reference_solid_iges(const std::string& path, double radius_mm, double height_mm) {
  mute_opencascade();
  const TopoDS_Shape cylinder = BRepPrimAPI_MakeCylinder(radius_mm, height_mm).Shape();
  const TopoDS_Shape sphere = BRepBuilderAPI_NurbsConvert(
                                  BRepPrimAPI_MakeSphere(gp_Pnt(3.0 * radius_mm, 0, 0.5 * height_mm), radius_mm).Shape())
                                  .Shape();
  TopoDS_Compound both;
  BRep_Builder builder;
  builder.MakeCompound(both);
  builder.Add(both, cylinder);
  builder.Add(both, sphere);
  IGESControl_Controller::Init();
  IGESControl_Writer writer("MM", 1);  // 1: BRep mode (faces, shells, solids)
  if (!writer.AddShape(both) || (writer.ComputeModel(), !writer.Write(path.c_str())))
    throw IoError(path + ": OpenCASCADE could not write the IGES file");
}

void write_vertex_only_step(const std::string& path) {
  mute_opencascade();
  STEPControl_Writer writer;
  const TopoDS_Shape vertex = BRepBuilderAPI_MakeVertex(gp_Pnt(1, 2, 3)).Shape();
  if (writer.Transfer(vertex, STEPControl_AsIs) != IFSelect_RetDone || writer.Write(path.c_str()) != IFSelect_RetDone)
    throw IoError(path + ": OpenCASCADE could not write the STEP file");
}

} // namespace hb::vtk
