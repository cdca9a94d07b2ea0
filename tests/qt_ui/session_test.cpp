// The logic without widgets: session files, the background job, the model's hash, the jobs'
// default recipe, the report shared with the command line.
#include "BackgroundJob.h"
#include "HapticSession.h"
#include "SessionFile.h"
#include "errors.h"
#include "exact/exact_query.h"
#include "SessionPipeline.h"
#include "recipe/box_cache.h"
#include "store/box_file.h"
#include "mesh/file_hash.h"
#include "device/servo_log.h"
#include "device/servo_loop.h"
#include "ui_test_support.h"
#include <QFile>
#include <QFileInfo>
#include <QProcess>
#include <nlohmann/json.hpp>
#include <gtest/gtest.h>
#include <vtkDataArray.h>
#include <vtkPointData.h>
#include <cmath>
#include <cstring>
#include <optional>
#include <thread>

TEST(SessionFileTest, RoundTripsEveryField) {
  QTemporaryDir dir;
  SessionState s;
  s.meshPath = dir.filePath("model.off");
  s.bake.advanced = true;
  s.bake.m = 24;
  s.bake.n = 6;
  s.bake.padding = 0.02f;
  s.bake.refine = true;
  s.baked = true;
  s.depthFraction = 0.03;
  s.tiltDegrees = 30;
  s.outlines = true;
  s.metric = ErrorMetric::Direction;
  s.hasCamera = true;
  s.camera.position = {1, 2, 3};
  s.hasProbe = true;
  s.probePoint = {0.5f, -1.25f, 7.f};
  saveSessionFile(s, dir.filePath("a.hbsession"));
  const SessionState t = loadSessionFile(dir.filePath("a.hbsession"));
  EXPECT_EQ(t.meshPath, s.meshPath);
  EXPECT_TRUE(t.bake.advanced);
  EXPECT_EQ(t.bake.m, 24);
  EXPECT_EQ(t.bake.n, 6);
  EXPECT_FLOAT_EQ(t.bake.padding, 0.02f);
  EXPECT_TRUE(t.bake.refine);
  EXPECT_TRUE(t.baked);
  EXPECT_DOUBLE_EQ(t.tiltDegrees, 30);
  EXPECT_TRUE(t.outlines);
  EXPECT_EQ(t.metric, ErrorMetric::Direction);
  EXPECT_EQ(t.camera.position[2], 3);
  EXPECT_TRUE(t.hasProbe);
  EXPECT_FLOAT_EQ(t.probePoint[1], -1.25f);
  s.hasProbe = false;  // a probe never placed stays unplaced
  saveSessionFile(s, dir.filePath("b.hbsession"));
  EXPECT_FALSE(loadSessionFile(dir.filePath("b.hbsession")).hasProbe);
}

TEST(SessionFileTest, GarbageIsInvalidInput) {
  QTemporaryDir dir;
  QFile f(dir.filePath("b.hbsession"));
  ASSERT_TRUE(f.open(QIODevice::WriteOnly));
  f.write("{ not json");
  f.close();
  EXPECT_THROW(loadSessionFile(dir.filePath("b.hbsession")), hb::InvalidInput);
  EXPECT_THROW(loadSessionFile(dir.filePath("missing.hbsession")), hb::IoError);
}

TEST(SessionFileTest, SessionNamingItselfOrAnotherSessionIsRefused) {
  QTemporaryDir dir;
  auto write = [&](const QString& name, const std::string& mesh) {
    QFile f(dir.filePath(name));
    EXPECT_TRUE(f.open(QIODevice::WriteOnly));
    f.write((R"({"format":"hapticbox-session","version":1,"mesh":")" + mesh + R"(","bake":{"recipe":"default"}})").c_str());
    return dir.filePath(name);
  };
  auto refusal = [](const QString& path) -> std::string {
    try {
      loadSessionFile(path);
    } catch (const hb::InvalidInput& e) {
      return e.what();
    }
    return "accepted";
  };
  // Itself, by its own name and by a path that comes back to it.
  const QString self = write("self.hbsession", "self.hbsession");
  std::string why = refusal(self);
  EXPECT_NE(why.find("self.hbsession: \"mesh\" names this session file itself"), std::string::npos) << why;
  EXPECT_NE(refusal(write("dots.hbsession", "./sub/../dots.hbsession")).find("itself"), std::string::npos);
  // A cycle of two: each refused at its first step, so no open can follow the cycle.
  const QString a = write("a.hbsession", "b.hbsession");
  write("b.hbsession", "a.hbsession");
  why = refusal(a);
  EXPECT_NE(why.find("names the session file"), std::string::npos) << why;
  EXPECT_NE(why.find("b.hbsession"), std::string::npos) << why;
  // A session under another name is still a session; a missing .hbsession too (by its name).
  write("session.json", "model.off");
  EXPECT_NE(refusal(write("c.hbsession", "session.json")).find("session.json"), std::string::npos);
  EXPECT_NE(refusal(write("d.hbsession", "gone.HBSESSION")).find("gone.HBSESSION"), std::string::npos);
  // A model is still a model.
  EXPECT_EQ(refusal(write("e.hbsession", "model.off")), "accepted");
}

TEST(BackgroundJobTest, CancelStopsTheWorkAndReportsCancelled) {
  BackgroundJob job;
  bool finished = false, cancelled = false;
  QObject::connect(&job, &BackgroundJob::finished, [&](bool, bool c, const QString&) {
    finished = true;
    cancelled = c;
  });
  ASSERT_TRUE(job.start("spin", [](const auto& progress) {
    for (int i = 0;; ++i) {
      if (!progress(0.0)) throw hb::Cancelled("spin cancelled");
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
  }));
  EXPECT_FALSE(job.start("second", [](const auto&) {}));
  job.cancel();
  ASSERT_TRUE(hbtest::waitFor([&] { return finished; }, 10));
  EXPECT_TRUE(cancelled);
  EXPECT_FALSE(job.isRunning());
}


namespace {

// summary.json without what differs between two runs of the same report: timings (and what
// is derived from them: the Pareto front, speed verdicts), cache hits, the image and its note.
nlohmann::json withoutTimings(const nlohmann::json& j) {
  if (j.is_array()) {
    nlohmann::json out = nlohmann::json::array();
    for (const auto& x : j) out.push_back(withoutTimings(x));
    return out;
  }
  if (!j.is_object()) return j;
  nlohmann::json out = nlohmann::json::object();
  for (auto it = j.begin(); it != j.end(); ++it) {
    const std::string& k = it.key();
    bool timing = false;
    for (const char* w : {"_ns", "seconds", "timing", "pareto", "from_cache", "image", "note", "faster", "slower",
                          "speedup", "loaded_from_file", "stamp", "command_line", "date", "machine", "host", "verdict", "generated",
                          "summary_text"})
      timing |= k.find(w) != std::string::npos;
    if (!timing) out[k] = withoutTimings(*it);
  }
  return out;
}

nlohmann::json readJson(const QString& path) {
  QFile f(path);
  if (!f.open(QIODevice::ReadOnly)) return {};
  return nlohmann::json::parse(f.readAll().toStdString());
}

/// Bakes the open model into a small explicit box (m 8, n 4: not the default recipe) and waits.
void bakeSmallBox(HapticSession& s) {
  BakeSettings b = s.bakeSettings();
  b.advanced = true;
  b.m = 8;
  b.n = 4;
  s.setBakeSettings(b);
  ASSERT_TRUE(s.startBake());
  ASSERT_TRUE(hbtest::waitFor([&] { return !s.job()->isRunning(); }, 300));
}

}  // namespace

// The window's Export Error Report and `hapticbox report BOX MESH` build one ReportRequest
// (report/report_request.h): the same box and mesh give the same summary.json, timings aside,
// with the references' real memory and build times.
TEST(SessionReportTest, WindowAndCommandLineGiveTheSameReport) {
  hbtest::MeshDir data;
  HapticSession s;
  ASSERT_TRUE(s.openMesh(data.mesh));
  ASSERT_NO_FATAL_FAILURE(bakeSmallBox(s));
  ASSERT_TRUE(s.hasBoxes());
  const QString box = data.dir.filePath(QStringLiteral("bumpy.hbox"));
  ASSERT_TRUE(s.saveBoxFile(box));
  ASSERT_TRUE(s.openBoxFile(box));

  const QString windowDir = data.dir.filePath(QStringLiteral("window-report"));
  QString error;
  ASSERT_TRUE(s.startReport(windowDir, QString(), 1000, &error)) << error.toStdString();
  ASSERT_TRUE(hbtest::waitFor([&] { return !s.job()->isRunning(); }, 300));

  const QString cliDir = data.dir.filePath(QStringLiteral("cli-report"));
  QProcess cli;
  cli.start(QStringLiteral(HB_CLI_PATH), {QStringLiteral("report"), box, s.meshPath(), QStringLiteral("-o"), cliDir,
                                          QStringLiteral("--samples"), QStringLiteral("1000"), QStringLiteral("--field"), QStringLiteral("image=off")});
  ASSERT_TRUE(cli.waitForFinished(300000));
  ASSERT_EQ(cli.exitCode(), 0) << cli.readAllStandardError().toStdString();

  const nlohmann::json window = readJson(windowDir + "/summary.json"), line = readJson(cliDir + "/summary.json");
  ASSERT_FALSE(window.is_null());
  ASSERT_FALSE(line.is_null());
  EXPECT_EQ(withoutTimings(window).dump(1), withoutTimings(line).dump(1));
  // Both measured the same references, with their real costs.
  for (const nlohmann::json* j : {&window, &line}) {
    bool exact = false, vtk = false;
    for (const auto& row : (*j)["sweep"]) {
      if (row["method"] == "exact_embree") exact = row["memory_bytes"].get<double>() > 0;
      if (row["method"] == "vtk_static_cell_locator") vtk = row["memory_bytes"].get<double>() > 0;
    }
    EXPECT_TRUE(exact);
    EXPECT_TRUE(vtk);
  }
  EXPECT_GT(window["sweep"].size(), 2u);  // the default sweep ran in the window too
}

// The window hashes its input with the command line's hb::hash_model, a DICOM folder
// included, so a box it bakes is accepted by `hapticbox eval` (which refuses a box baked from
// another model) and both share cache entries.
TEST(SessionModelTest, WindowAndCommandLineHashAFolderTheSame) {
  const QString series = QStringLiteral(HB_DATASETS_DIR "/volumes/dicom/CT5N");
  const QString debian =
      QStringLiteral("/usr/lib/python3/dist-packages/pydicom/data/test_files/dicomdirtests/98892001/CT5N");
  const QString folder = QFileInfo::exists(series) ? series : debian;
  ASSERT_TRUE(QFileInfo::exists(folder)) << "no DICOM series: datasets/fetch.sh unpacks python3-pydicom's CT5N into "
                                         << series.toStdString();
  hbtest::MeshDir data;  // its own box cache
  HapticSession s;
  QString error;
  ASSERT_TRUE(s.openMesh(folder, &error)) << error.toStdString();
  EXPECT_EQ(s.meshHash(), hb::hash_model(QFile::encodeName(folder).toStdString()));
  BakeSettings b = s.bakeSettings();
  b.advanced = true;
  b.m = 8;
  b.n = 4;
  s.setBakeSettings(b);
  ASSERT_TRUE(s.startBake(&error)) << error.toStdString();
  ASSERT_TRUE(hbtest::waitFor([&] { return !s.job()->isRunning(); }, 300));
  ASSERT_TRUE(s.hasBoxes());
  EXPECT_EQ(s.boxes()->parts().source.mesh_hash, s.meshHash());
  const QString box = data.dir.filePath(QStringLiteral("series.hbox"));
  ASSERT_TRUE(s.saveBoxFile(box));
  QProcess cli;
  cli.start(QStringLiteral(HB_CLI_PATH), {QStringLiteral("eval"), box, folder, QStringLiteral("--samples"),
                                          QStringLiteral("200"), QStringLiteral("--json")});
  ASSERT_TRUE(cli.waitForFinished(120000));
  EXPECT_EQ(cli.exitCode(), 0) << cli.readAllStandardError().toStdString();
}

// By default the window's Bake is `hapticbox bake MESH -o BOX`: hb::default_recipe() (the
// budgeted bake, automatic pieces, block codec) through hb::bake. The advanced settings
// bake exactly the sampling given.
TEST(SessionJobsTest, DefaultBakeIsTheCommandLinesDefaultRecipe) {
  const BakeSettings defaults;
  EXPECT_FALSE(defaults.advanced);
  EXPECT_EQ(hb::recipe_key(defaults.recipe()), hb::recipe_key(hb::default_recipe()));
  EXPECT_TRUE(defaults.recipe().budget.enabled);
  BakeSettings advanced;
  advanced.advanced = true;
  advanced.m = 12;
  advanced.n = 6;
  const hb::BakeRecipe r = advanced.recipe();
  EXPECT_FALSE(r.budget.enabled);
  EXPECT_EQ(r.options.params.m, 12);
  EXPECT_EQ(r.options.params.n, 6);
  EXPECT_NE(hb::recipe_key(r), hb::recipe_key(hb::default_recipe()));
}

// The window's error field runs the pipeline's vtkHapticBoxErrorFieldFilter on the bake
// filter's boxes and the session's exact reference; the view's arrays are its output's and hold
// what hb::compute_error_field gives on the same boxes, the same mesh (the reader's surface
// converts back bit for bit) and a fresh exact query: the same numbers, bit for bit.
TEST(SessionJobsTest, ErrorFieldArraysAreTheFiltersAndTheCoresNumbers) {
  hbtest::MeshDir data;
  HapticSession s;
  ASSERT_TRUE(s.openMesh(data.mesh));
  ASSERT_NO_FATAL_FAILURE(bakeSmallBox(s));
  ASSERT_TRUE(s.hasBoxes());
  QString error;
  ASSERT_TRUE(s.startErrorField(2, &error)) << error.toStdString();
  ASSERT_TRUE(hbtest::waitFor([&] { return !s.job()->isRunning(); }, 300));
  ASSERT_TRUE(s.hasErrorField());

  const hb::ExactQuery exact(s.mesh());
  hb::ErrorFieldOptions o;
  o.probes_per_point = 2;
  o.law = s.model()->law();  // the window's forces are at the model's workspace scale
  const hb::ErrorField core =
      hb::compute_error_field(*s.boxes(), exact, hb::surface_points_at_vertices(s.mesh()), s.diagonal(), o);
  ASSERT_EQ(core.size(), s.mesh().vertex_count());
  const struct {
    ErrorMetric metric;
    const std::vector<float>* values;
  } arrays[] = {{ErrorMetric::RelativeForce, &core.force_error},
                {ErrorMetric::Direction, &core.direction_error},
                {ErrorMetric::ContactDisagreement, &core.contact_disagreement}};
  for (const auto& a : arrays) {
    vtkDataArray* shown = s.surface()->GetPointData()->GetArray(HapticSession::errorArrayName(a.metric));
    ASSERT_NE(shown, nullptr) << HapticSession::errorArrayName(a.metric);
    ASSERT_EQ(static_cast<std::size_t>(shown->GetNumberOfTuples()), a.values->size());
    std::size_t same = 0;
    for (std::size_t i = 0; i < a.values->size(); ++i) {
      const double v = shown->GetTuple1(static_cast<vtkIdType>(i)), w = (*a.values)[i];
      same += (std::isnan(v) && std::isnan(w)) || v == w ? 1 : 0;
    }
    EXPECT_EQ(same, a.values->size()) << HapticSession::errorArrayName(a.metric);
  }
  EXPECT_FALSE(s.model()->pipeline()->errorField()->GetBuiltExact());
  EXPECT_EQ(s.errorField()->probes, core.probes);
}

namespace {

// `hapticbox ARGS...`: exit code and standard output.
std::pair<int, QByteArray> runCli(const QStringList& args) {
  QProcess cli;
  cli.start(QStringLiteral(HB_CLI_PATH), args);
  if (!cli.waitForFinished(600000)) return {-1, {}};
  return {cli.exitCode(), cli.readAllStandardOutput()};
}

}  // namespace

// The window's Bake at its default settings (its pipeline's bake filter, hb::default_recipe()
// through hb::bake_cached) and `hapticbox bake MESH -o BOX --cache none` (a bake of its own, not
// the window's cache entry) give the same boxes: the window's cache entry and the box the window
// saves are the same bytes, and the CLI's file is too but for the query times its bake measured
// (the budget report keeps no wall time; BudgetReport::without_times leaves out the query
// times). Same bytes, same answers: eval and query read nothing else.
TEST(SessionJobsTest, DefaultBakeGivesTheCommandLinesBoxes) {
  hbtest::MeshDir data;
  // A coarse sphere (320 triangles): the default bake tunes on 20,000 probes whatever the size.
  hb::BumpySphereOptions o;
  o.radius = 50.f;
  o.subdivisions = 2;
  const QString mesh = data.dir.filePath(QStringLiteral("coarse.off"));
  hb::write_mesh(hb::make_bumpy_sphere(o), QFile::encodeName(mesh).toStdString());
  HapticSession s;
  ASSERT_TRUE(s.openMesh(mesh));
  ASSERT_FALSE(s.bakeSettings().advanced);
  QString error;
  ASSERT_TRUE(s.startBake(&error)) << error.toStdString();
  ASSERT_TRUE(hbtest::waitFor([&] { return !s.job()->isRunning(); }, 600));
  ASSERT_TRUE(s.hasBoxes());
  EXPECT_TRUE(s.boxes()->parts().budget.present);
  const QString window = data.dir.filePath(QStringLiteral("window.hbox"));
  const QString line = data.dir.filePath(QStringLiteral("line.hbox"));
  ASSERT_TRUE(s.saveBoxFile(window));
  ASSERT_EQ(runCli({QStringLiteral("bake"), s.meshPath(), QStringLiteral("-o"), line, QStringLiteral("--cache"), QStringLiteral("none")}).first, 0);
  // The window baked through its pipeline's bake filter into the box cache entry of the mesh
  // hash and the default recipe.
  const std::string entry = hb::BoxCache().path_for(s.meshHash(), hb::default_recipe());
  ASSERT_EQ(s.model()->pipeline()->bake()->GetCachePath(), entry);
  const auto bytes = [](const QString& path) {
    QFile f(path);
    return f.open(QIODevice::ReadOnly) ? f.readAll() : QByteArray();
  };
  // A box file's bytes with its bake-time query times left out, written again.
  const auto untimed = [&](const QString& path) {
    hb::BoxScene scene = hb::load_box_file(QFile::encodeName(path).toStdString());
    scene = hb::with_budget(scene, scene.parts().budget.without_times());
    const QString out = data.dir.filePath(QFileInfo(path).fileName() + QStringLiteral(".untimed"));
    hb::save_box_file(scene, QFile::encodeName(out).toStdString());
    return bytes(out);
  };
  const QByteArray cached = bytes(QString::fromStdString(entry));
  ASSERT_GT(cached.size(), 0);
  EXPECT_TRUE(bytes(window) == cached) << "the window's saved box differs from its cache entry";
  const QByteArray written = untimed(line);
  ASSERT_GT(written.size(), 0);
  EXPECT_TRUE(untimed(QString::fromStdString(entry)) == written) << "the window's cache entry differs from `hapticbox bake`'s file";
  EXPECT_TRUE(untimed(window) == written) << "the window's saved box differs from `hapticbox bake`'s file";
}

// The window's servo thread and `hapticbox servo` run the same box file at one workspace
// (hb::scene_workspace: the probe, the scale and the stiffness): at every device position the
// command line's loop recorded, the window's servo options give the command line's force
// (its driving answer before safety), bit for bit.
TEST(SessionDeviceTest, WindowAndCommandLineServoForcesAgreeBitForBit) {
  hbtest::MeshDir data;
  HapticSession s;
  ASSERT_TRUE(s.openMesh(data.mesh));
  ASSERT_NO_FATAL_FAILURE(bakeSmallBox(s));
  ASSERT_TRUE(s.hasBoxes());
  ASSERT_TRUE(hbtest::waitFor([&] { return s.device()->servoRunning(); }, 30));
  const std::optional<hb::ServoOptions> window = s.device()->servoOptions();
  ASSERT_TRUE(window.has_value());
  const QString box = data.dir.filePath(QStringLiteral("bumpy.hbox"));
  const QString log = data.dir.filePath(QStringLiteral("servo.hbslog"));
  ASSERT_TRUE(s.saveBoxFile(box));
  const auto [code, out] = runCli({QStringLiteral("servo"), box, QStringLiteral("--exact"), data.mesh,
                                   QStringLiteral("--device"), QStringLiteral("virtual"), QStringLiteral("--seconds"),
                                   QStringLiteral("0.5"), QStringLiteral("--no-realtime"), QStringLiteral("--record"), log});
  ASSERT_EQ(code, 0) << out.toStdString();
  const hb::ServoLog recorded = hb::read_servo_log(QFile::encodeName(log).toStdString());
  ASSERT_TRUE(recorded.comparison);
  ASSERT_EQ(recorded.shadow.size(), recorded.records.size());
  ASSERT_GT(recorded.records.size(), 100u);

  // The window's servo thread: its probe over its boxes, its workspace's probe and law.
  hb::SceneProbe probe(*s.boxes());
  const hb::ForceLaw law = window->workspace.law();
  std::size_t contacts = 0, same = 0;
  for (std::size_t i = 0; i < recorded.records.size(); ++i) {
    const float* p = recorded.records[i].position_m;
    const hb::Contact c = probe.query(window->workspace.probe(hb::Vec3(p[0], p[1], p[2])), law);
    const float* f = recorded.shadow[i].drive_force_n;
    same += std::memcmp(c.force.data(), f, 3 * sizeof(float)) == 0 ? 1 : 0;
    contacts += c.contact ? 1 : 0;
  }
  EXPECT_EQ(same, recorded.records.size());
  EXPECT_GT(contacts, 10u);
}
