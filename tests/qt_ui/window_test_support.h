#pragma once
// Helpers of the tests that drive a whole MainWindow: a small bake, the probe placed.
#include "BackgroundJob.h"
#include "BakePanel.h"
#include "HapticSession.h"
#include "MainWindow.h"
#include "ProbeView.h"
#include "ui_test_support.h"
#include <QPushButton>
#include <vtkRenderWindow.h>
#include <gtest/gtest.h>

namespace hbtest {

inline void setSmallBake(HapticSession& s, int m = 8, int n = 4) {
  BakeSettings b = s.bakeSettings();
  b.advanced = true;  // an explicit small sampling, not the default recipe's budgeted bake
  b.m = m;
  b.n = n;
  s.setBakeSettings(b);
}

/// Opens the mesh and bakes a small box through the panel's Bake button.
inline void openAndBake(MainWindow& w, const QString& mesh) {
  w.setBakeOnOpen(false);
  ASSERT_TRUE(w.openFile(mesh));
  setSmallBake(*w.session());
  w.bakePanel()->showSettings();
  w.bakePanel()->bakeButton()->click();
  ASSERT_TRUE(waitFor([&] { return w.session()->hasBoxes() && !w.session()->job()->isRunning(); }));
}

/// Places the probe on the model at the centre of the view, aimed along the view direction.
inline bool placeProbe(MainWindow& w) {
  ProbeView* v = w.probeView();
  const int* size = v->renderWindow()->GetSize();
  hb::Vec3 p;
  if (!v->pickSurface(size[0] / 2, size[1] / 2, p)) return false;
  w.session()->aimProbe(v->viewDirection(), v->viewRight());
  w.session()->setProbeTarget(p);
  return true;
}

}  // namespace hbtest
