// Damaged files the mutation campaign (tests/fuzz/mutate_campaign.cpp) found accepted or
// crashing a reader, and the IGES faults the mutation campaign found, each through load_model (the path the
// CLI and the window take, readers in their child process): a clear error naming the file and
// the cause, never a crash, a silently different model or a silent change of unit.
#include "errors.h"
#include "mesh/generators.h"
#include "model_loader.h"
#include "formats/iges_check.h"
#include "formats/iges_global.h"
#include "polydata_files.h"
#include <gtest/gtest.h>
#include <vtkPolyData.h>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#ifdef HB_HAVE_OCCT
#include "cad_reader.h"
#endif
#ifdef HB_HAVE_ASSIMP
#include "scene_reader.h"
#endif

namespace {

namespace fs = std::filesystem;

class DamagedModelsTest : public ::testing::Test {
protected:
  static void SetUpTestSuite() {
    dir_ = fs::temp_directory_path() / ("hb_damaged_models_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  static void TearDownTestSuite() { fs::remove_all(dir_); }
  static std::string path(const std::string& name) { return (dir_ / name).string(); }
  static std::string slurp(const std::string& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  }
  static std::string write(const std::string& name, const std::string& bytes) {
    std::ofstream(path(name), std::ios::binary) << bytes;
    return path(name);
  }
  static std::string replaced(std::string text, const std::string& from, const std::string& to) {
    const std::size_t at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    if (at != std::string::npos) text.replace(at, from.size(), to);
    return text;
  }
  // load_model must throw hb::InvalidInput starting with `file` + ": ", holding `cause`.
  static void expect_refused(const std::string& file, const std::string& cause, const hb::vtk::ModelOptions& o = {}) {
    try {
      hb::vtk::load_model(file, o);
      ADD_FAILURE() << file << ": loaded";
    } catch (const hb::InvalidInput& e) {
      const std::string m = e.what();
      EXPECT_EQ(m.rfind(file + ": ", 0), 0u) << m;
      EXPECT_NE(m.find(cause), std::string::npos) << "expected '" << cause << "' in: " << m;
    }
  }
  static fs::path dir_;
};
fs::path DamagedModelsTest::dir_;

#ifdef HB_HAVE_OCCT
hb::vtk::ModelOptions coarse() {
  hb::vtk::ModelOptions o;
  o.cad.chordal_deviation_mm = 0.1;
  return o;
}

TEST_F(DamagedModelsTest, StepReferenceToAMissingInstanceIsRefusedBeforeOpenCascade) {
  // The campaign's most common STEP crash: a reference changed to #0 or to an id the file
  // does not define (OpenCASCADE's translator: a segmentation fault).
  hb::vtk::write_reference_solid_step(path("solid.step"), 10.0, 30.0);
  const std::string good = slurp(path("solid.step"));
  const std::size_t face = good.find("ADVANCED_FACE");
  ASSERT_NE(face, std::string::npos);
  const std::size_t ref = good.find('#', face);
  const std::size_t ref_end = good.find_first_not_of("0123456789", ref + 1);
  std::string missing = good, zero = good;
  missing.replace(ref, ref_end - ref, "#999999");
  zero.replace(ref, ref_end - ref, "#0");
  expect_refused(write("missing.step", missing), "refers to #999999, which the file does not define", coarse());
  expect_refused(write("zero.step", zero), "refers to #0", coarse());
  // An instance defined twice.
  const std::size_t first = good.find("\n#", good.find("DATA;")) + 1;
  std::string twice = good;
  twice.insert(first, "#2 = CARTESIAN_POINT('',(0.,0.,0.));\n");
  expect_refused(write("twice.step", twice), "is defined twice", coarse());
  EXPECT_NO_THROW(hb::vtk::load_model(path("solid.step"), coarse()));
}

TEST_F(DamagedModelsTest, StepParameterOfTheWrongKindOrASyntaxErrorIsRefusedNamingTheInstance) {
  // OpenCASCADE's reader records these and goes on; its translator then followed what the
  // reader left unset (the campaign's remaining STEP crashes: segmentation faults).
  hb::vtk::write_reference_solid_step(path("solid.step"), 10.0, 30.0);
  const std::string good = slurp(path("solid.step"));
  expect_refused(write("number.step", replaced(good, "= VERTEX_POINT('',#45);", "= VERTEX_POINT('',0);")),
                 "the STEP file is damaged at instance #44: Parameter n0.2 (vertex_geometry) not an Entity", coarse());
  // #1 is defined (the reference check passes), but is no direction.
  expect_refused(write("kind.step", replaced(good, "= VECTOR('',#62,1.);", "= VECTOR('',#1,1.);")),
                 "damaged at instance #61: Parameter n0.2 (orientation) : Entity has illegal type", coarse());
  expect_refused(write("spelling.step", replaced(good, "= VECTOR('',#62,1.);", "= VCTOR('',#62,1.);")),
                 "the STEP file is damaged", coarse());
  expect_refused(write("junk.step", replaced(good, "= VERTEX_POINT('',#45);", "= VERTEX_POINT(''\x01#45);")),
                 "the STEP file is damaged", coarse());
  // Read as 1.5 without a word: the cylinder's axis tilted.
  expect_refused(write("fraction.step", replaced(good, "#21 = DIRECTION('',(0.,0.,1.));", "#21 = DIRECTION('',(1.5.,0.,1.));")),
                 "STEP instance #21 holds '1.5.', not a number", coarse());
  // An exponent that overflows: OpenCASCADE's translator was still busy after 60 s.
  expect_refused(write("overflow.step", replaced(good, "#79 = CARTESIAN_POINT('',(10.,-2.449293598295E-15,0.));",
                                                 "#79 = CARTESIAN_POINT('',(10.,-2.449293598295E65535,0.));")),
                 "STEP instance #79 holds -2.449293598295E65535, beyond any model's range (1e100)", coarse());
}

TEST_F(DamagedModelsTest, StepParenthesesNestedTooDeepOrUnbalancedAreRefusedBeforeOpenCascade) {
  hb::vtk::write_reference_solid_step(path("solid.step"), 10.0, 30.0);
  const std::string good = slurp(path("solid.step"));
  const std::string point = "#21 = DIRECTION('',(0.,0.,1.));";
  // 100,000 nested parentheses: OpenCASCADE's parser recursed until its stack overflowed.
  const std::string deep = "#21 = DIRECTION(''," + std::string(100000, '(') + "0.,0.,1." + std::string(100000, ')') + ");";
  expect_refused(write("deep.step", replaced(good, point, deep)), "STEP instance #21 nests parentheses more than 100 deep", coarse());
  expect_refused(write("open.step", replaced(good, point, "#21 = DIRECTION('',(0.,0.,1.);")), "STEP instance #21 ends with 1 parentheses left open",
                 coarse());
  expect_refused(write("close.step", replaced(good, point, "#21 = DIRECTION('',(0.,0.,1.)));")),
                 "STEP instance #21 closes a parenthesis it never opened", coarse());
}

TEST_F(DamagedModelsTest, StepInstanceNumberBeyondAnIntIsRefusedBeforeOpenCascade) {
  hb::vtk::write_reference_solid_step(path("solid.step"), 10.0, 30.0);
  const std::string good = slurp(path("solid.step"));
  const std::size_t at = good.find("\n#140 = ");
  ASSERT_NE(at, std::string::npos);
  std::string big = good;
  big.replace(at + 1, 4, "#2147483648");  // OpenCASCADE's reader crashed
  expect_refused(write("big.step", big), "STEP instance number #2147483648 is beyond 2147483647", coarse());
}

TEST_F(DamagedModelsTest, IgesDamagedDirectoryOrParameterDataIsRefusedBeforeOpenCascade) {
  // The campaign's IGES crashes (segmentation faults in OpenCASCADE's translator, a quarter of
  // the damaged IGES files): a directory line lost, a parameter line's entry number damaged,
  // a pointer to the wrong kind of entity, an index past its list, a count past the values.
  hb::vtk::write_reference_solid_iges(path("solid.igs"), 10.0, 30.0);
  const std::string good = slurp(path("solid.igs"));
  const std::size_t d9 = good.find("D0000009\n");
  ASSERT_NE(d9, std::string::npos);
  std::string lost = good;
  lost.erase(good.rfind('\n', d9) + 1, d9 + 9 - good.rfind('\n', d9) - 1);
  expect_refused(write("d_lost.igs", lost), "is numbered '0000010' where D9 belongs (a line missing, repeated or damaged)", coarse());
  std::string entry = good;
  const std::size_t p2 = good.find("0000003P0000002");
  ASSERT_NE(p2, std::string::npos);
  entry[p2 + 3] = 'X';
  expect_refused(write("p_entry.igs", entry), "P line 2 (line 89) belongs to D000X003, but directory entry D3", coarse());
  // The second shell's face: D69 -> D57, a point (116).
  expect_refused(write("kind.igs", replaced(good, "514,1,69,1;", "514,1,57,1;")), "points to D57, of type 116", coarse());
  // A loop's edge: index 1 -> 9 into the 4 edges of list D19.
  expect_refused(write("index.igs", replaced(good, "508,1,0,19,1,1,0;", "508,1,0,19,9,1,0;")), "index 9 into D19, a list of 4", coarse());
  expect_refused(write("count.igs", replaced(good, "510,43,1,1,51;", "510,43,7,1,51;")), "its count 7 (value 2) does not fit", coarse());
  // A B-spline curve's first weight 1 -> 0, and a NUL inside one of its knots: OpenCASCADE
  // read both (the NUL ending the number) and the sphere's face collapsed to a sliver.
  const std::string spline = "6.283185307,7.853981634,7.853981634,7.853981634,1.,1.,1.,1.,1.,";
  const std::size_t d77 = good.find(spline);
  ASSERT_NE(d77, std::string::npos);
  std::string weight = good, nul_knot = good;
  weight[d77 + spline.find("1.,")] = '0';
  nul_knot[d77 + 18] = '\0';
  expect_refused(write("weight.igs", weight), "entity D77 (type 126): weight 1 (value 15) is not positive", coarse());
  expect_refused(write("nul_knot.igs", nul_knot), "holds the control byte \\x00 in column 19", coarse());
  // The terminate line's counts.
  expect_refused(write("t.igs", replaced(good, "D     82P", "D     80P")), "the terminate line counts 'D     80' where the file has D82", coarse());
  EXPECT_NO_THROW(hb::check_iges_structure("x", good));
}

TEST_F(DamagedModelsTest, IgesFaceTiltedAwayFromItsEdgesIsRefusedBeforeTheMesher) {
  // The cylinder's axis (the first direction, 123) from (0, 0, 1) to (1, 0, 1): well-formed,
  // but its edges no longer lie on it; OpenCASCADE widened their tolerance to 18 mm and its
  // mesher ran past 120 s (823 MB). Refused after the transfer, in about a second.
  hb::vtk::write_reference_solid_iges(path("solid.igs"), 10.0, 30.0);
  const std::string tilted = write("tilted.igs", replaced(slurp(path("solid.igs")), "123,0.,0.,1.;", "123,1.,0.,1.;"));
  hb::vtk::ModelOptions o = coarse();
  o.reader_timeout_s = 60.0;
  expect_refused(tilted, "its edges miss their faces by up to", o);
  expect_refused(tilted, "meshing it would not end", o);
}

TEST_F(DamagedModelsTest, StepPlaneMovedOffItsEdgesStopsRefiningWithAWarning) {
  // The cylinder's bottom plane 1 mm off its circle: the measured deviation stays at 1 mm
  // however fine the mesh, and the refinement rounds (each finer by 0.9 x asked / measured)
  // ran to 3 GB and past 120 s. Now at most 10x finer a round, and no round after one that
  // did not bring the deviation closer: a mesh, and a warning that says why it is off.
  hb::vtk::write_reference_solid_step(path("solid.step"), 10.0, 30.0);
  const std::string moved = write("moved.step", replaced(slurp(path("solid.step")), "#117 = CARTESIAN_POINT('',(0.,0.,0.));",
                                                         "#117 = CARTESIAN_POINT('',(0.,0.,1.));"));
  hb::vtk::ModelOptions o = coarse();
  o.reader_timeout_s = 60.0;
  const hb::vtk::LoadedModel m = hb::vtk::load_model(moved, o);
  EXPECT_GT(m.mesh.triangle_count(), 0u);
  EXPECT_LT(m.mesh.triangle_count(), 100000u);
  ASSERT_FALSE(m.report.warnings.empty());
  EXPECT_NE(m.report.warnings.back().find("a finer mesh did not bring it closer"), std::string::npos) << m.report.warnings.back();
}

TEST_F(DamagedModelsTest, IgesReferenceSolidLoadsInMillimetres) {
  hb::vtk::write_reference_solid_iges(path("solid.igs"), 10.0, 30.0);
  const hb::vtk::LoadedModel m = hb::vtk::load_model(path("solid.igs"), coarse());
  EXPECT_EQ(m.format, "IGES");
  EXPECT_EQ(m.facts["faces"], 4);
  EXPECT_EQ(m.facts["face_types"]["bspline"], 1);
  EXPECT_EQ(m.facts["file_mm_per_unit"], 1.0);
  // Cylinder r 10 h 30 at the origin, sphere r 10 at (30, 0, 15): x from -10 to 40 mm.
  EXPECT_NEAR(m.mesh.bounds().max.x(), 40.0, 0.1);
  EXPECT_NEAR(m.mesh.bounds().max.z(), 30.0, 0.1);
}

TEST_F(DamagedModelsTest, IgesBSplineOfTooHighADegreeIsRefusedBeforeOpenCascade) {
  hb::vtk::write_reference_solid_iges(path("solid.igs"), 10.0, 30.0);
  // The sphere's B-spline surface (entity 128): K1 = 6 (7 control points in u), degree M1 2 -> 9
  // (OpenCASCADE crashed on some such surfaces, dropped the face on others).
  const std::string good = slurp(path("solid.igs"));
  const std::string bad = write("degree.igs", replaced(good, "\n128,6,4,2,2,", "\n128,6,4,9,2,"));
  expect_refused(bad, "(type 128): its degree in u (value 3) is 9 but its 7 control points in u allow a degree from 1 to 6", coarse());
  hb::vtk::ModelOptions accept = coarse();
  accept.cad.accept_lost_faces = true;  // not a lost face: a damaged file
  expect_refused(bad, "its degree in u", accept);
  expect_refused(write("degree0.igs", replaced(good, "\n128,6,4,2,2,", "\n128,6,4,2,0,")), "its degree in v (value 4) is 0", coarse());
  // More control points than the values hold.
  expect_refused(write("points.igs", replaced(good, "\n128,6,4,2,2,", "\n128,9,4,2,2,")), "need", coarse());
}

TEST_F(DamagedModelsTest, IgesCurveRangeOutsideItsKnotsOrLinesRunTogetherAreRefusedBeforeOpenCascade) {
  // Both crashed OpenCASCADE (or kept it busy past the reader's limit) in a fresh campaign.
  hb::vtk::write_reference_solid_iges(path("solid.igs"), 10.0, 30.0);
  const std::string good = slurp(path("solid.igs"));
  expect_refused(write("knots.igs", replaced(good, "126,1,1,1,0,1,0,0.,0.,6.283185307,", "126,1,1,1,0,1,0,0.,0.,1.283185307,")),
                 "(type 126): its parameter range 0.000000 to 6.283185 (values 19-20) is not within its knots' span 0.000000 to 1.283185",
                 coarse());
  const std::size_t p = good.find("P0000057\n");
  ASSERT_NE(p, std::string::npos);
  std::string joined = good;
  joined.insert(p + 8, "5.,40.,17.320508076,25.,");
  expect_refused(write("joined.igs", joined), "has text past column 80", coarse());
}

TEST_F(DamagedModelsTest, IgesDamagedGlobalSectionIsRefusedNeverASilentUnitSwitch) {
  hb::vtk::write_reference_solid_iges(path("solid.igs"), 10.0, 30.0);
  const std::string good = slurp(path("solid.igs"));
  // OpenCASCADE read each of these in another unit without a word (inches: 25.4 x, flag 9:
  // micrometres), or from a section it could not parse.
  expect_refused(write("flag_inch.igs", replaced(good, ",1.,2,2HMM,", ",1.,1,2HMM,")),
                 "unit flag 1 (field 14) and unit name 'MM' (field 15) disagree", coarse());
  expect_refused(write("flag_micron.igs", replaced(good, ",1.,2,2HMM,", ",1.,9,2HMM,")), "disagree", coarse());
  expect_refused(write("name_inch.igs", replaced(good, ",1.,2,2HMM,", ",1.,2,2HIN,")), "disagree", coarse());
  expect_refused(write("hollerith.igs", replaced(good, ",1.,2,2HMM,", ",1.,2,5HMM,")), "the IGES global section is damaged", coarse());
  // A G line lost: the fields after it shift.
  const std::size_t g3 = good.find("G0000003");
  ASSERT_NE(g3, std::string::npos);
  const std::size_t start = good.rfind('\n', g3) + 1;
  std::string cut = good;
  cut.erase(start, g3 + 9 - start);
  expect_refused(write("g_line.igs", cut), "length unit cannot be trusted", coarse());
  // An explicit flag 3 takes the name.
  EXPECT_DOUBLE_EQ(hb::iges_mm_per_unit("x", replaced(good, ",1.,2,2HMM,", ",1.,3,2HCM,")), 10.0);
  EXPECT_DOUBLE_EQ(hb::iges_mm_per_unit("x", replaced(good, ",1.,2,2HMM,", ",1.,1,2HIN,")), 25.4);
}
#endif

#ifdef HB_HAVE_ASSIMP
TEST_F(DamagedModelsTest, FbxArrayHoldingMoreOrFewerValuesThanDeclaredIsRefused) {
  const hb::TriangleMesh sphere = hb::make_sphere(25.f, 3);
  hb::vtk::write_scene(sphere, path("s.fbx"));
  const std::string good = slurp(path("s.fbx"));
  if (good.compare(0, 18, "Kaydara FBX Binary") == 0) GTEST_SKIP() << "Assimp wrote a binary FBX";
  // A stretch of the polygon indices repeated (the campaign's case: Assimp read 5,603
  // triangles of the elephant's 5,558 and said nothing).
  const std::size_t at = good.find("PolygonVertexIndex: *");
  ASSERT_NE(at, std::string::npos);
  const std::size_t a = good.find("a: ", at) + 3;
  std::string repeated = good;
  repeated.insert(a, good.substr(a, good.find(',', a + 40) + 1 - a));
  expect_refused(write("repeated.fbx", repeated), "the FBX array PolygonVertexIndex declares");
  // An index past the vertices.
  std::string far = good;
  far.insert(a, "99999,");
  far = replaced(far, "PolygonVertexIndex: *", "PolygonVertexIndex: *1");  // keep the count plausible, then fix it below
  const std::size_t star = far.find("PolygonVertexIndex: *") + 21;
  const std::size_t brace = far.find(' ', star);
  const unsigned long declared = std::stoul(good.substr(good.find("PolygonVertexIndex: *") + 21)) + 1;
  far.replace(star, brace - star, std::to_string(declared));
  expect_refused(write("far.fbx", far), "refers to vertex 99999");
  EXPECT_NO_THROW(hb::vtk::load_model(path("s.fbx")));
}

TEST_F(DamagedModelsTest, ColladaPolylistWithoutItsSizesOrIndicesIsRefused) {
  const hb::TriangleMesh sphere = hb::make_sphere(25.f, 3);
  hb::vtk::write_scene(sphere, path("s.dae"));
  const std::string good = slurp(path("s.dae"));
  const std::size_t v = good.find("<vcount>");
  if (v == std::string::npos) GTEST_SKIP() << "Assimp wrote no polylist";
  // The <vcount> line deleted (the campaign's Collada crash).
  const std::size_t line = good.rfind('\n', v) + 1;
  std::string cut = good;
  cut.erase(line, good.find('\n', v) + 1 - line);
  expect_refused(write("novcount.dae", cut), "sizes in its <vcount>");
  // An index too many in <p>.
  expect_refused(write("extra.dae", replaced(good, "<p>", "<p>0 ")), "indices in its <p>");
  EXPECT_NO_THROW(hb::vtk::load_model(path("s.dae")));
}

TEST_F(DamagedModelsTest, ThreeMfDamagedZipEntryOrMissingRootPartIsRefusedNotAnAbort) {
  const hb::TriangleMesh sphere = hb::make_sphere(25.f, 3);
  hb::vtk::write_scene(sphere, path("s.3mf"));
  const std::string good = slurp(path("s.3mf"));
  // Damage the model part's deflated bytes (the campaign's most common 3MF case: Assimp's unzip
  // failed, and its assertion on the missing root stream aborted the process).
  const std::size_t local = good.find("3D/3DModel.model") != std::string::npos ? good.find("3D/3DModel.model")
                                                                                : good.find("3D/3dmodel.model");
  ASSERT_NE(local, std::string::npos);
  std::string flipped = good;
  for (std::size_t k = local + 60; k < local + 400 && k < flipped.size(); k += 7) flipped[k] = char(flipped[k] ^ 0x55);
  expect_refused(write("flipped.3mf", flipped), "is damaged (");
  // The CRC-32 in the model part's local header (the campaign's remaining 3MF abort).
  std::string crc = good;
  const std::size_t header = crc.rfind("PK\x03\x04", local);
  ASSERT_NE(header, std::string::npos);
  crc[header + 14] = char(0xFF);
  crc[header + 15] = char(0xFF);
  expect_refused(write("crc.3mf", crc), "local header disagrees");
  // The root relationship renamed away.
  expect_refused(write("norels.3mf", replaced(replaced(good, "_rels/.rels", "_rels/.relx"), "_rels/.rels", "_rels/.relx")),
                 "no _rels/.rels part");
  EXPECT_NO_THROW(hb::vtk::load_model(path("s.3mf")));
}
#endif

TEST_F(DamagedModelsTest, VtpPieceFileWithARepeatedArrayOrTagOrADamagedBlockIsRefusedBeforeVtk) {
  // The campaign's contained cases: VTK's XML reader crashed on a repeated PieceId line, ran
  // past 8 GB on a repeated AppendedData tag, and went on after a zlib error.
  const hb::TriangleMesh sphere = hb::make_sphere(20.f, 3);
  std::vector<std::uint32_t> ids(sphere.triangle_count());
  for (std::size_t t = 0; t < ids.size(); ++t) ids[t] = std::uint32_t(t % 4);
  hb::vtk::write_polydata_xml(hb::vtk::piece_polydata(sphere, ids), path("pieces.vtp"));
  const std::string good = slurp(path("pieces.vtp"));
  ASSERT_NE(good.find("compressor="), std::string::npos);
  EXPECT_EQ(hb::vtk::read_piece_vtp(path("pieces.vtp"), ids.size()), ids);
  auto refused = [&](const std::string& name, const std::string& bytes, const std::string& cause) {
    const std::string file = write(name, bytes);
    try {
      hb::vtk::read_piece_vtp(file, ids.size());
      ADD_FAILURE() << name << ": read";
    } catch (const hb::InvalidInput& e) {
      EXPECT_EQ(std::string(e.what()).rfind(file + ": ", 0), 0u) << e.what();
      EXPECT_NE(std::string(e.what()).find(cause), std::string::npos) << e.what();
    }
  };
  const std::size_t line = good.find("<DataArray type=\"Int32\" Name=\"PieceId\"");
  ASSERT_NE(line, std::string::npos);
  const std::size_t line_end = good.find('\n', line) + 1;
  std::string twice = good;
  twice.insert(line_end, good.substr(line, line_end - line));
  refused("twice.vtp", twice, "array PieceId appears twice in the CellData section");
  refused("tag.vtp", replaced(good, "<AppendedData encoding=\"raw\">", "<AppendedData encoding=\"raw\">\n  <AppendedData encoding=\"raw\">"),
          "between the AppendedData tag and its '_'");
  // A token before the '_' (VTK's reader spun for minutes).
  refused("token.vtp", replaced(good, "   _", "  #999999 _"), "between the AppendedData tag and its '_'");
  std::string block = good;
  const std::size_t end = block.rfind("</AppendedData>");
  ASSERT_NE(end, std::string::npos);
  const std::size_t trailer = block.find_last_not_of(" \n", end - 1) - 1;  // in the last stream's Adler-32
  block[trailer] = char(block[trailer] ^ 0x5A);
  refused("block.vtp", block, "does not inflate");
}

TEST_F(DamagedModelsTest, DicomSliceWithItsMarkerShiftedIsNamedNotDropped) {
  fs::path series = fs::path(HB_DATASETS_DIR) / "volumes" / "dicom" / "CT5N";
  if (!fs::exists(series)) series = "/usr/lib/python3/dist-packages/pydicom/data/test_files/dicomdirtests/98892001/CT5N";
  if (!fs::exists(series)) GTEST_SKIP() << "no CT5N series (datasets/fetch.sh)";
  const fs::path copy = dir_ / "CT5N";
  fs::remove_all(copy);
  fs::copy(series, copy);
  std::vector<fs::path> slices;
  for (const auto& e : fs::directory_iterator(copy)) slices.push_back(e.path());
  std::sort(slices.begin(), slices.end());
  ASSERT_EQ(slices.size(), 5u);
  // 112 bytes repeated inside the preamble: "DICM" moves from byte 128 to 240. The reader
  // dropped the slice and made a volume of 4 (the lost slice at an end leaves no gap).
  const std::string victim = slices.back().string();
  const std::string bytes = slurp(victim);
  std::ofstream(victim, std::ios::binary) << bytes.substr(0, 112) + bytes;
  try {
    hb::vtk::load_model(copy.string());
    ADD_FAILURE() << "a series of 4 slices loaded";
  } catch (const hb::InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find(victim + ": not a DICOM file"), std::string::npos) << e.what();
  }
}

} // namespace
