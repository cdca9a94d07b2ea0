// The window's Bake runs the VTK pipeline the design names (reader -> decomposition filter ->
// bake filter -> error-field filter) and gives `hapticbox bake`'s box: on a real model with
// automatic pieces, the window's cache entry is the box cache's (hb::BoxCache::path_for of the
// file's hb::hash_model and the recipe) and holds the very bytes `hapticbox bake MESH -o BOX
// --pieces auto ...` writes; the views draw the filters' outputs; reopening opens the cached
// entry without decomposing. (The default recipe, the same pipeline with the budget, is
// compared byte for byte on a coarse sphere in SessionJobsTest.DefaultBakeGivesTheCommandLinesBoxes:
// on a real model it bakes for 20 s to 2 min here.)
#include "BackgroundJob.h"
#include "BakePanel.h"
#include "HapticSession.h"
#include "MainWindow.h"
#include "ProbeView.h"
#include "SessionPipeline.h"
#include "recipe/box_cache.h"
#include "mesh/file_hash.h"
#include "vtkHapticBoxSet.h"
#include "window_test_support.h"
#include <QFile>
#include <QFileInfo>
#include <QImage>
#include <QProcess>
#include <QPushButton>
#include <vtkCellData.h>
#include <vtkFieldData.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

using hbtest::pump;
using hbtest::waitFor;

namespace {

QByteArray fileBytes(const QString& path) {
  QFile f(path);
  return f.open(QIODevice::ReadOnly) ? f.readAll() : QByteArray();
}

// A real model of the datasets (1,050 triangles, several automatic pieces).
QString realModel() { return QStringLiteral(HB_DATASETS_DIR "/meshes/anchor.off"); }

}  // namespace

TEST(WindowPipelineTest, BakeRunsThePipelineAndCachesTheCommandLinesBox) {
  const QString model = realModel();
  ASSERT_TRUE(QFileInfo::exists(model)) << model.toStdString() << " is missing: run datasets/fetch.sh";
  hbtest::MeshDir data;  // its own XDG cache
  MainWindow w;
  w.show();
  w.setBakeOnOpen(false);
  ASSERT_TRUE(w.openFile(model));
  HapticSession& s = *w.session();
  // A small sampling with automatic pieces, as `hapticbox bake -m 8 -n 4 --pieces auto`.
  BakeSettings settings = s.bakeSettings();
  settings.advanced = true;
  settings.m = 8;
  settings.n = 4;
  settings.pieces = BakeSettings::Pieces::Automatic;
  s.setBakeSettings(settings);
  const hb::BakeRecipe recipe = settings.recipe();
  ASSERT_FALSE(s.hasBoxes());
  w.bakePanel()->showSettings();
  w.bakePanel()->bakeButton()->click();
  ASSERT_TRUE(waitFor([&] { return s.hasBoxes() && !s.job()->isRunning(); }, 600));

  // The pipeline ran: the bake filter read the decomposition filter's output (automatic
  // pieces, the recipe's options) and stored its scene in the box cache.
  SessionPipeline* p = s.model()->pipeline();
  ASSERT_NE(p, nullptr);
  EXPECT_EQ(p->bake()->GetInputAlgorithm(), p->decomposition());
  EXPECT_EQ(p->decomposition()->GetInputAlgorithm(), p->reader());
  EXPECT_NE(p->decomposition()->GetOutput()->GetFieldData()->GetAbstractArray("DecompositionOptions"), nullptr);
  EXPECT_GT(p->decomposition()->GetOutput()->GetNumberOfCells(), 0);
  EXPECT_FALSE(p->bake()->GetFromCache());
  EXPECT_EQ(p->bake()->GetBoxSet()->GetScene(), s.model()->sharedBoxes());
  const std::string path = QFile::encodeName(model).toStdString();
  const std::string entry = hb::BoxCache().path_for(hb::hash_model(path), recipe);
  EXPECT_EQ(p->bake()->GetCachePath(), entry);
  ASSERT_TRUE(QFileInfo::exists(QString::fromStdString(entry))) << entry;
  EXPECT_GT(s.boxes()->parts().boxes.size(), 1u);

  // `hapticbox bake MESH -o BOX -m 8 -n 4 --pieces auto` (the same absolute path the window
  // records) writes the same bytes.
  const QString line = data.dir.filePath(QStringLiteral("line.hbox"));
  QProcess cli;
  cli.start(QStringLiteral(HB_CLI_PATH), {QStringLiteral("bake"), s.meshPath(), QStringLiteral("-o"), line,
                                          QStringLiteral("-m"), QStringLiteral("8"), QStringLiteral("-n"),
                                          QStringLiteral("4"), QStringLiteral("--pieces"), QStringLiteral("auto"),
                                          QStringLiteral("--cache"), QStringLiteral("none")});
  ASSERT_TRUE(cli.waitForFinished(600000));
  ASSERT_EQ(cli.exitCode(), 0) << cli.readAllStandardError().toStdString();
  const QByteArray cached = fileBytes(QString::fromStdString(entry)), written = fileBytes(line);
  ASSERT_GT(cached.size(), 0);
  EXPECT_EQ(cached.size(), written.size());
  EXPECT_TRUE(cached == written) << "the window's cache entry differs from `hapticbox bake`'s file";
  // One box cache for both front ends: the same command through the cache (the session's
  // XDG_CACHE_HOME) finds the window's entry and copies it instead of baking.
  const QString copied = data.dir.filePath(QStringLiteral("copied.hbox"));
  QProcess hit;
  hit.start(QStringLiteral(HB_CLI_PATH), {QStringLiteral("bake"), s.meshPath(), QStringLiteral("-o"), copied,
                                          QStringLiteral("-m"), QStringLiteral("8"), QStringLiteral("-n"),
                                          QStringLiteral("4"), QStringLiteral("--pieces"), QStringLiteral("auto"),
                                          QStringLiteral("--json")});
  ASSERT_TRUE(hit.waitForFinished(120000));
  ASSERT_EQ(hit.exitCode(), 0) << hit.readAllStandardError().toStdString();
  const nlohmann::json hitJson = nlohmann::json::parse(hit.readAllStandardOutput().toStdString(), nullptr, false);
  EXPECT_EQ(hitJson.value("from_cache", false), true) << hitJson.dump();
  EXPECT_EQ(hitJson.value("cache_path", std::string()), entry);
  EXPECT_TRUE(fileBytes(copied) == cached);

  // The views draw the filters' outputs: the outlines are the bake filter's output 1 (shared
  // points), the piece ids its output 3's array.
  vtkPolyData* outlines = p->bake()->GetOutput(1);
  ASSERT_GT(outlines->GetNumberOfLines(), 12);
  EXPECT_EQ(s.outlines()->GetPoints()->GetData(), outlines->GetPoints()->GetData());
  EXPECT_EQ(s.surface()->GetCellData()->GetArray("PieceId"), p->bake()->GetOutput(3)->GetCellData()->GetArray("PieceId"));

  // What the window shows after the Bake: the pieces' colours and the outlines (the bake
  // filter's outputs 3 and 1).
  w.probeView()->setOutlinesVisible(true);
  pump(0.5);
  w.refresh();
  const QString baked = data.dir.filePath(QStringLiteral("after_bake.png"));
  ASSERT_TRUE(w.exportScreenshot(baked));
  EXPECT_FALSE(QImage(baked).isNull());
  if (qEnvironmentVariableIsSet("HB_UI_TEST_SHOTS")) {  // for a person to look at
    const QString dir = qEnvironmentVariable("HB_UI_TEST_SHOTS");
    QFile::remove(dir + QStringLiteral("/window_after_bake.png"));
    QFile::copy(baked, dir + QStringLiteral("/window_after_bake.png"));
    w.grab().save(dir + QStringLiteral("/whole_window_after_bake.png"));
  }

  // The error field: the error-field filter on the bake filter's boxes, against the session's
  // exact reference (not a second Embree scene); the view's arrays are its output's.
  QString error;
  ASSERT_TRUE(s.startErrorField(1, &error)) << error.toStdString();
  ASSERT_TRUE(waitFor([&] { return !s.job()->isRunning(); }, 300));
  ASSERT_TRUE(s.hasErrorField());
  EXPECT_FALSE(p->errorField()->GetBuiltExact());
  EXPECT_EQ(p->errorField()->GetInputAlgorithm(1, 0), p->bake());
  EXPECT_EQ(s.surface()->GetPointData()->GetArray("RelativeForceError"),
            p->errorField()->GetOutput()->GetPointData()->GetArray("RelativeForceError"));

  if (qEnvironmentVariableIsSet("HB_UI_TEST_SHOTS")) {
    pump(0.5);
    w.refresh();
    const QString dir = qEnvironmentVariable("HB_UI_TEST_SHOTS");
    QFile::remove(dir + QStringLiteral("/window_error_field.png"));
    w.exportScreenshot(dir + QStringLiteral("/window_error_field.png"));
  }

  // Reopening the model opens the cached entry through the bake filter: no decomposition (the
  // .hbox file holds the piece ids), the same pieces.
  const std::vector<std::uint32_t> pieces = s.boxes()->parts().piece_of_triangle;
  MainWindow again;
  again.setBakeOnOpen(false);
  again.session()->setBakeSettings(settings);
  ASSERT_TRUE(again.openFile(model));
  HapticSession& t = *again.session();
  ASSERT_TRUE(t.hasBoxes());
  EXPECT_TRUE(t.boxesFromCache());
  SessionPipeline* q = t.model()->pipeline();
  EXPECT_TRUE(q->bake()->GetFromCache());
  EXPECT_EQ(q->bake()->GetInputAlgorithm(), q->reader());
  EXPECT_EQ(q->decomposition()->GetOutput()->GetNumberOfCells(), 0) << "the decomposition ran on reopening";
  EXPECT_EQ(t.boxes()->parts().piece_of_triangle, pieces);
  EXPECT_EQ(t.surface()->GetCellData()->GetArray("PieceId"), q->bake()->GetOutput(3)->GetCellData()->GetArray("PieceId"));
}
