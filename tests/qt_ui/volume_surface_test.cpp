// The medical path in the window: a volume opens with its surface panel (histogram, Otsu,
// iso-value in HU, label, smoothing, target triangles); Extract re-reads it with those options
// (the hash as the command line's with the same options); the bone iso of the synthesized femur
// CT finds the femur within a voxel of the surface it was made from; a DICOM folder opens through
// its own action's path.
#include "SurfacePanel.h"
#include "SessionFile.h"
#include "errors.h"
#include "mesh/mesh_io.h"
#include "model_options_key.h"
#include "volume_spec.h"
#include "mesh/file_hash.h"
#include "window_test_support.h"
#include <QAction>
#include <QCheckBox>
#include <QDoubleSpinBox>
#include <QMouseEvent>
#include <QElapsedTimer>
#include <QFileInfo>
#include <QTimer>
#include <QPushButton>
#include <QSpinBox>
#include <vtkCellArray.h>
#include <vtkGenericCell.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkStaticCellLocator.h>
#include <cmath>

using hbtest::pump;
using hbtest::waitFor;

namespace {

const QString kFemurCt = QStringLiteral(HB_DATASETS_DIR "/generated/femur_ct.nii.gz");
const QString kFemurSource = QStringLiteral(HB_DATASETS_DIR "/generated/femur_ct_source.off");

vtkSmartPointer<vtkPolyData> polyData(const hb::TriangleMesh& m) {
  auto points = vtkSmartPointer<vtkPoints>::New();
  for (const hb::Vec3& p : m.positions) points->InsertNextPoint(p.x(), p.y(), p.z());
  auto cells = vtkSmartPointer<vtkCellArray>::New();
  for (const auto& t : m.triangles) {
    const vtkIdType ids[3] = {t[0], t[1], t[2]};
    cells->InsertNextCell(3, ids);
  }
  auto pd = vtkSmartPointer<vtkPolyData>::New();
  pd->SetPoints(points);
  pd->SetPolys(cells);
  return pd;
}

/// The largest distance from a vertex of `from` to the surface `to`, and how many vertices
/// lie farther than `limit`.
std::pair<double, std::size_t> farthest(const hb::TriangleMesh& from, const hb::TriangleMesh& to, double limit) {
  auto surface = polyData(to);
  auto locator = vtkSmartPointer<vtkStaticCellLocator>::New();
  locator->SetDataSet(surface);
  locator->BuildLocator();
  auto cell = vtkSmartPointer<vtkGenericCell>::New();
  double worst = 0;
  std::size_t beyond = 0;
  for (const hb::Vec3& p : from.positions) {
    double x[3] = {p.x(), p.y(), p.z()}, closest[3], d2 = 0;
    vtkIdType id = 0;
    int sub = 0;
    locator->FindClosestPoint(x, closest, cell, id, sub, d2);
    worst = std::max(worst, std::sqrt(d2));
    if (std::sqrt(d2) > limit) ++beyond;
  }
  return {worst, beyond};
}

}  // namespace

TEST(VolumeSurfaceTest, TheBoneIsoOfTheFemurCtFindsTheFemurWithinAVoxel) {
  if (!QFileInfo::exists(kFemurCt)) GTEST_SKIP() << "run datasets/fetch.sh build/datasets/hb_generate_datasets";
  hbtest::MeshDir data;  // its own box cache
  MainWindow w;
  w.show();
  w.setBakeOnOpen(false);
  ASSERT_TRUE(w.openFile(kFemurCt));
  SurfacePanel* panel = w.surfacePanel();
  ASSERT_TRUE(w.session()->model()->isVolume());
  EXPECT_TRUE(panel->extractButton()->isEnabled());
  // Opened at the automatic iso-value, the Otsu threshold: the panel shows it, between air and soft tissue.
  const double otsu = w.session()->model()->otsu();
  EXPECT_NEAR(panel->isoBox()->value(), otsu, 1.0);
  EXPECT_NEAR(w.session()->model()->modelFacts()["iso"].get<double>(), otsu, 0.5 * w.session()->model()->histogram().bin_width() + 0.1);
  EXPECT_LT(otsu, -100.0);
  EXPECT_GT(otsu, -900.0);
  const std::uint64_t skinHash = w.session()->meshHash();

  // The bone: 300 HU, every triangle (no smoothing, no decimation), as Extract Surface re-reads it.
  panel->isoBox()->setValue(300.0);
  panel->smoothBox()->setValue(0);
  panel->targetBox()->setValue(0);
  panel->extractButton()->click();
  ASSERT_TRUE(w.session()->model()->modelOptions().volume.iso.has_value());
  EXPECT_DOUBLE_EQ(*w.session()->model()->modelOptions().volume.iso, 300.0);
  EXPECT_NE(w.session()->meshHash(), skinHash);
  hb::vtk::ModelOptions cli;  // what `hapticbox bake femur_ct.nii.gz --volume iso=300` hashes
  hb::vtk::parse_volume_spec("iso=300", cli.volume);
  EXPECT_EQ(w.session()->meshHash(), hb::hash_model(kFemurCt.toStdString(), hb::vtk::model_options_key(cli)));

  const hb::TriangleMesh source = hb::read_mesh(kFemurSource.toStdString());
  const hb::TriangleMesh& bone = w.session()->mesh();
  const double voxel = 1.0;  // mm (hb::vtk::MeshCtOptions::voxel_mm)
  // Every point the bone iso finds lies within a voxel of the femur's surface.
  const auto [boneToSource, boneFar] = farthest(bone, source, voxel);
  EXPECT_EQ(boneFar, 0u) << "worst " << boneToSource << " mm";
  EXPECT_LT(boneToSource, voxel);
  // And it finds the whole femur: its area, and its surface within a voxel except where two
  // sheets of femur.off lie closer than a voxel (at the condyles: no 1 mm CT resolves that gap,
  // the blur fills it with bone; typically 88.8 % of the source's vertices within 1 mm,
  // 98.0 % within 2 mm).
  const auto [sourceToBone, sourceFar] = farthest(source, bone, voxel);
  const auto [sourceToBone2, sourceFar2] = farthest(source, bone, 2.0 * voxel);
  const double n = double(source.vertex_count());
  std::printf("femur CT at 300 HU: %zu triangles, area %.0f mm2 (source %.0f); bone to source max %.3f mm; source "
              "vertices within 1 mm %.1f %%, within 2 mm %.1f %%, max %.2f mm\n",
              bone.triangle_count(), bone.area(), source.area(), boneToSource, 100.0 * (1.0 - double(sourceFar) / n),
              100.0 * (1.0 - double(sourceFar2) / n), sourceToBone);
  EXPECT_NEAR(bone.area(), source.area(), 0.02 * source.area());
  EXPECT_GE(1.0 - double(sourceFar) / n, 0.85);
  EXPECT_GE(1.0 - double(sourceFar2) / n, 0.97);
  (void)sourceToBone2;
  // The panel states what it extracted.
  EXPECT_NEAR(panel->isoBox()->value(), 300.0, 1e-9);
  if (const char* keep = std::getenv("HB_SCREENSHOT_DIR")) w.grab().save(QString::fromLocal8Bit(keep) + "/femur_surface_panel.png");
}

TEST(VolumeSurfaceTest, TheFemurCtAsADicomSeriesGivesTheSameBone) {
  const QString series = QStringLiteral(HB_DATASETS_DIR "/generated/femur_ct_dicom");
  if (!QFileInfo(series).isDir()) GTEST_SKIP() << "run datasets/fetch.sh build/datasets/hb_generate_datasets";
  hbtest::MeshDir data;
  MainWindow w;
  w.show();
  w.setBakeOnOpen(false);
  hb::vtk::ModelOptions bone;
  bone.volume.iso = 300.0;
  ASSERT_TRUE(w.openFile(series, false, bone));  // what File > Open DICOM Folder then Extract at 300 HU give
  EXPECT_EQ(QString::fromStdString(w.session()->model()->modelFacts().value("format", std::string())), QStringLiteral("DICOM series"));
  const hb::TriangleMesh source = hb::read_mesh(kFemurSource.toStdString());
  const auto [boneToSource, boneFar] = farthest(w.session()->mesh(), source, 1.0);
  EXPECT_EQ(boneFar, 0u) << "worst " << boneToSource << " mm";
  EXPECT_NEAR(w.session()->mesh().area(), source.area(), 0.02 * source.area());
}

TEST(VolumeSurfaceTest, SurfacePanelOptionsAndAClickOnTheHistogramChooseTheIso) {
  const QString phantom = QStringLiteral(HB_DATASETS_DIR "/generated/ct_phantom.nii.gz");
  if (!QFileInfo::exists(phantom)) GTEST_SKIP() << "run datasets/fetch.sh build/datasets/hb_generate_datasets";
  hbtest::MeshDir data;
  MainWindow w;
  w.show();
  w.setBakeOnOpen(false);
  ASSERT_TRUE(w.openFile(phantom));
  SurfacePanel* panel = w.surfacePanel();
  VolumeHistogramView* h = panel->histogramView();
  // A click on the histogram sets the iso-value to the value under it.
  const int x = h->width() * 3 / 4;
  QMouseEvent press(QEvent::MouseButtonPress, QPointF(x, h->height() / 2), Qt::LeftButton, Qt::LeftButton, Qt::NoModifier);
  QApplication::sendEvent(h, &press);
  EXPECT_NEAR(panel->isoBox()->value(), h->valueAt(x), 0.051);
  const std::size_t before = w.session()->mesh().triangle_count();
  panel->isoBox()->setValue(370.0);  // the phantom's bone (halfway between soft tissue and bone)
  panel->smoothBox()->setValue(15);
  panel->targetBox()->setValue(2000);
  panel->extractButton()->click();
  const hb::vtk::ModelOptions& o = w.session()->model()->modelOptions();
  EXPECT_EQ(o.volume.smooth_iterations, 15);
  EXPECT_EQ(o.volume.target_triangles, 2000u);
  EXPECT_NE(w.session()->mesh().triangle_count(), before);
  EXPECT_LE(w.session()->mesh().triangle_count(), 2400u);
  // The label map: a label instead of an iso-value.
  ASSERT_TRUE(w.openFile(QStringLiteral(HB_DATASETS_DIR "/generated/ct_phantom_labels.nii.gz")));
  panel->labelCheck()->setChecked(true);
  panel->labelBox()->setValue(2);
  // The live preview of a label (its voxels subsampled, never averaged into other labels).
  ASSERT_TRUE(hbtest::waitFor([&] { return !panel->previewPending() && w.probeView()->previewTriangles() > 0; }, 60));
  EXPECT_TRUE(panel->statusText().contains(QStringLiteral("Preview at label 2"))) << panel->statusText().toStdString();
  panel->extractButton()->click();
  EXPECT_EQ(w.probeView()->previewTriangles(), 0);
  ASSERT_TRUE(w.session()->model()->modelOptions().volume.label.has_value());
  EXPECT_EQ(*w.session()->model()->modelOptions().volume.label, 2);
  EXPECT_FALSE(panel->isoBox()->isEnabled());
  // A mesh disables the panel and says why.
  hbtest::MeshDir mesh;
  ASSERT_TRUE(w.openFile(mesh.mesh));
  EXPECT_FALSE(panel->extractButton()->isEnabled());
}

TEST(VolumeSurfaceTest, ADicomFolderHasItsOwnOpenAction) {
  const QString series = QStringLiteral(HB_DATASETS_DIR "/volumes/dicom/CT5N");
  if (!QFileInfo(series).isDir()) GTEST_SKIP() << "run datasets/fetch.sh";
  hbtest::MeshDir data;
  MainWindow w;
  w.show();
  w.setBakeOnOpen(false);
  QAction* action = w.findChild<QAction*>(QStringLiteral("openDicomFolderAction"));
  ASSERT_NE(action, nullptr);
  EXPECT_TRUE(action->text().contains(QStringLiteral("DICOM")));
  // What the action does with the folder the dialog returns.
  ASSERT_TRUE(w.openFile(series));
  EXPECT_TRUE(w.session()->model()->isVolume());
  EXPECT_TRUE(w.surfacePanel()->extractButton()->isEnabled());
  EXPECT_EQ(QString::fromStdString(w.session()->model()->modelFacts().value("format", std::string())), QStringLiteral("DICOM series"));
}

TEST(VolumeSurfaceTest, ASessionKeepsTheSurfaceSettingsAndReopensThatSurface) {
  const QString phantom = QStringLiteral(HB_DATASETS_DIR "/generated/ct_phantom.nii.gz");
  if (!QFileInfo::exists(phantom)) GTEST_SKIP() << "run datasets/fetch.sh build/datasets/hb_generate_datasets";
  hbtest::MeshDir data;
  const QString session = data.dir.filePath(QStringLiteral("phantom.hbsession"));
  std::size_t triangles = 0;
  std::uint64_t hash = 0;
  {
    MainWindow w;
    w.show();
    w.setBakeOnOpen(false);
    ASSERT_TRUE(w.openFile(phantom));
    SurfacePanel* panel = w.surfacePanel();
    panel->isoBox()->setValue(370.0);
    panel->smoothBox()->setValue(12);
    panel->targetBox()->setValue(3000);
    panel->extractButton()->click();
    triangles = w.session()->mesh().triangle_count();
    hash = w.session()->meshHash();
    ASSERT_TRUE(w.saveSession(session));
  }
  // In the file, in the command line's terms.
  const SessionState s = loadSessionFile(session);
  ASSERT_TRUE(s.hasSurface);
  ASSERT_TRUE(s.surface.iso.has_value());
  EXPECT_DOUBLE_EQ(*s.surface.iso, 370.0);
  EXPECT_FALSE(s.surface.label.has_value());
  EXPECT_EQ(s.surface.smooth_iterations, 12);
  EXPECT_EQ(s.surface.target_triangles, 3000u);
  // A new window opening the session reads the same surface, and its panel shows the settings.
  MainWindow w;
  w.show();
  w.setBakeOnOpen(false);
  ASSERT_TRUE(w.openFile(session));
  const hb::vtk::ModelOptions& o = w.session()->model()->modelOptions();
  ASSERT_TRUE(o.volume.iso.has_value());
  EXPECT_DOUBLE_EQ(*o.volume.iso, 370.0);
  EXPECT_EQ(o.volume.smooth_iterations, 12);
  EXPECT_EQ(o.volume.target_triangles, 3000u);
  EXPECT_EQ(w.session()->mesh().triangle_count(), triangles);
  EXPECT_EQ(w.session()->meshHash(), hash);
  EXPECT_NEAR(w.surfacePanel()->isoBox()->value(), 370.0, 1e-9);
  EXPECT_EQ(w.surfacePanel()->smoothBox()->value(), 12);
  EXPECT_EQ(w.surfacePanel()->targetBox()->value(), 3000);
  // A label map's label round-trips too; a file naming both an iso-value and a label is refused.
  SessionState l = s;
  l.surface.iso.reset();
  l.surface.label = 2;
  saveSessionFile(l, data.dir.filePath(QStringLiteral("label.hbsession")));
  const SessionState m = loadSessionFile(data.dir.filePath(QStringLiteral("label.hbsession")));
  ASSERT_TRUE(m.surface.label.has_value());
  EXPECT_EQ(*m.surface.label, 2);
  EXPECT_FALSE(m.surface.iso.has_value());
  l.surface.iso = 5.0;
  saveSessionFile(l, data.dir.filePath(QStringLiteral("both.hbsession")));
  try {
    loadSessionFile(data.dir.filePath(QStringLiteral("both.hbsession")));
    ADD_FAILURE() << "a session with an iso-value and a label was accepted";
  } catch (const hb::InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("both.hbsession"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("iso-value and a label"), std::string::npos) << e.what();
  }
}

TEST(VolumeSurfaceTest, TheSurfacePanelPreviewsIsoAndSmoothingLiveWhileTheWindowStaysResponsive) {
  if (!QFileInfo::exists(kFemurCt)) GTEST_SKIP() << "run datasets/fetch.sh build/datasets/hb_generate_datasets";
  hbtest::MeshDir data;
  MainWindow w;
  w.resize(1229, 691);
  w.show();
  w.setBakeOnOpen(false);
  ASSERT_TRUE(w.openFile(kFemurCt));  // the Otsu threshold: the skin
  SurfacePanel* panel = w.surfacePanel();
  ProbeView* view = w.probeView();
  ASSERT_TRUE(panel->previewCheck()->isChecked());
  EXPECT_EQ(view->previewTriangles(), 0);  // opening previews nothing: the model is the surface
  const std::size_t modelTriangles = w.session()->mesh().triangle_count();
  const std::uint64_t modelHash = w.session()->meshHash();
  // The GUI thread's longest pause while previews are computed (a 5 ms timer's largest gap).
  QElapsedTimer clock;
  clock.start();
  qint64 last = 0, longest = 0;
  QTimer ticker;
  ticker.setInterval(5);
  QObject::connect(&ticker, &QTimer::timeout, [&] {
    const qint64 now = clock.elapsed();
    longest = std::max(longest, now - last);
    last = now;
  });
  const auto previewed = [&] {
    return waitFor([&] { return !panel->previewPending() && view->previewTriangles() > 0; }, 60);
  };
  pump(1.0);  // the opened model's first renders (not a preview's)
  // Moving the iso to bone: a preview of the femur, in the view, before any bake.
  ticker.start();
  last = clock.elapsed();
  panel->smoothBox()->setValue(0);
  panel->isoBox()->setValue(300.0);
  ASSERT_TRUE(previewed());
  const vtkIdType bone = view->previewTriangles();
  EXPECT_EQ(std::size_t(bone), panel->previewTriangles());
  EXPECT_TRUE(panel->statusText().contains(QStringLiteral("Preview at iso 300.0"))) << panel->statusText().toStdString();
  std::printf("%s\n", qPrintable(panel->statusText()));
  // Back to soft tissue: another surface, another count.
  panel->isoBox()->setValue(-300.0);
  ASSERT_TRUE(waitFor([&] { return !panel->previewPending() && view->previewTriangles() != bone; }, 60));
  const vtkIdType skin = view->previewTriangles();
  std::printf("%s\n", qPrintable(panel->statusText()));
  EXPECT_NE(skin, bone);
  // Quick changes are debounced: one preview, of the value the controls rest at.
  for (double iso : {0.0, 100.0, 200.0, 300.0}) {
    panel->isoBox()->setValue(iso);
    pump(0.05);
  }
  ASSERT_TRUE(waitFor([&] { return !panel->previewPending() && view->previewTriangles() == bone; }, 60));
  // Smoothing moves the preview's points (same triangles).
  double before[3];
  view->preview()->GetPoint(0, before);
  vtkPolyData* unsmoothed = view->preview();
  panel->smoothBox()->setValue(20);
  ASSERT_TRUE(waitFor([&] { return !panel->previewPending() && view->preview() != unsmoothed && view->preview(); }, 60));
  double after[3];
  view->preview()->GetPoint(0, after);
  EXPECT_GT(std::abs(after[0] - before[0]) + std::abs(after[1] - before[1]) + std::abs(after[2] - before[2]), 1e-6);
  ticker.stop();
  std::printf("femur CT preview: bone (300 HU) %lld triangles, soft tissue (-300 HU) %lld; longest GUI-thread pause "
              "while previewing %lld ms\n",
              static_cast<long long>(bone), static_cast<long long>(skin), static_cast<long long>(longest));
  // The window stayed responsive: the previews were computed off the GUI thread.
  EXPECT_LT(longest, 1000);
  if (const char* keep = std::getenv("HB_SCREENSHOT_DIR")) {  // for a person to look at
    view->viewAlong(1, 1);  // the femur from the side
    pump(0.3);
    w.exportScreenshot(QString::fromLocal8Bit(keep) + "/surface_preview.png");
    w.grab().save(QString::fromLocal8Bit(keep) + "/surface_preview_window.png");
  }
  // Nothing was baked or re-read: the model is still the skin until Extract Surface.
  EXPECT_EQ(w.session()->mesh().triangle_count(), modelTriangles);
  EXPECT_EQ(w.session()->meshHash(), modelHash);
  panel->extractButton()->click();
  EXPECT_EQ(view->previewTriangles(), 0);  // the extracted surface is the model now
  EXPECT_NE(w.session()->meshHash(), modelHash);
  // Turning the preview off drops it.
  panel->isoBox()->setValue(-300.0);
  ASSERT_TRUE(previewed());
  panel->previewCheck()->setChecked(false);
  EXPECT_EQ(view->previewTriangles(), 0);
}
