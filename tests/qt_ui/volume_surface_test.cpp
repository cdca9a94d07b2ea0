// The medical path in the window: a volume opens with its surface panel (histogram, Otsu,
// iso-value in HU, label, smoothing, target triangles); Extract re-reads it with those options
// (the hash as the command line's with the same options); the bone iso of the synthesized femur
// CT finds the femur within a voxel of the surface it was made from; a DICOM folder opens through
// its own action's path.
#include "SurfacePanel.h"
#include "mesh/mesh_io.h"
#include "model_options_key.h"
#include "mesh/file_hash.h"
#include "window_test_support.h"
#include <QAction>
#include <QCheckBox>
#include <QDoubleSpinBox>
#include <QFileInfo>
#include <QPushButton>
#include <QSpinBox>
#include <vtkCellArray.h>
#include <vtkGenericCell.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkStaticCellLocator.h>
#include <cmath>

using hbtest::pump;

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
  hb::vtk::ModelOptions cli;  // what `hapticbox bake femur_ct.nii.gz --iso 300` hashes
  cli.volume.iso = 300.0;
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
  // the blur fills it with bone; 2026-12-06: 88.8 % of the source's vertices within 1 mm,
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
  panel->extractButton()->click();
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
