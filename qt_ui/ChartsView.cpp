#include "ChartsView.h"
#include <QLabel>
#include <QHBoxLayout>
#include <QVBoxLayout>
#include <QVTKOpenGLNativeWidget.h>
#include <vtkAxis.h>
#include <vtkCallbackCommand.h>
#include <vtkChartLegend.h>
#include <vtkChartXY.h>
#include <vtkContextMouseEvent.h>
#include <vtkContextScene.h>
#include <vtkContextView.h>
#include <vtkDoubleArray.h>
#include <vtkGenericOpenGLRenderWindow.h>
#include <vtkIdTypeArray.h>
#include <vtkPlot.h>
#include <vtkPlotPoints.h>
#include <vtkRenderer.h>
#include <vtkStringArray.h>
#include <vtkTable.h>
#include <vtkTextProperty.h>
#include <cmath>

namespace {

vtkSmartPointer<vtkContextView> makeView(QVTKOpenGLNativeWidget* widget, vtkSmartPointer<vtkChartXY>& chart,
                                         const char* title, const char* x, const char* y) {
  auto window = vtkSmartPointer<vtkGenericOpenGLRenderWindow>::New();
  widget->setRenderWindow(window);
  auto view = vtkSmartPointer<vtkContextView>::New();
  view->SetRenderWindow(window);
  view->SetInteractor(widget->interactor());
  view->GetRenderer()->SetBackground(1, 1, 1);
  chart = vtkSmartPointer<vtkChartXY>::New();
  chart->SetTitle(title);
  chart->GetAxis(vtkAxis::BOTTOM)->SetTitle(x);
  chart->GetAxis(vtkAxis::LEFT)->SetTitle(y);
  chart->SetShowLegend(true);
  view->GetScene()->AddItem(chart);
  return view;
}

vtkPlot* addPoints(vtkChartXY* chart, const char* name, const std::vector<double>& xs, const std::vector<double>& ys,
                   unsigned char r, unsigned char g, unsigned char b, int marker) {
  auto table = vtkSmartPointer<vtkTable>::New();
  auto x = vtkSmartPointer<vtkDoubleArray>::New();
  x->SetName("x");
  auto y = vtkSmartPointer<vtkDoubleArray>::New();
  y->SetName(name);
  table->AddColumn(x);
  table->AddColumn(y);
  table->SetNumberOfRows(static_cast<vtkIdType>(xs.size()));
  for (std::size_t i = 0; i < xs.size(); ++i) {
    table->SetValue(static_cast<vtkIdType>(i), 0, xs[i]);
    table->SetValue(static_cast<vtkIdType>(i), 1, ys[i]);
  }
  vtkPlot* plot = chart->AddPlot(vtkChart::POINTS);
  plot->SetInputData(table, 0, 1);
  plot->SetColor(r, g, b, 255);
  plot->SetWidth(2.0);
  if (auto* points = vtkPlotPoints::SafeDownCast(plot)) {
    points->SetMarkerStyle(marker);
    points->SetMarkerSize(10.0);
  }
  return plot;
}

}  // namespace

ChartsView::ChartsView(QWidget* parent) : QWidget(parent) {
  speedWidget_ = new QVTKOpenGLNativeWidget;
  compressionWidget_ = new QVTKOpenGLNativeWidget;
  speedView_ = makeView(speedWidget_, speedChart_, "Speed against accuracy", "query time (ns, log)",
                        "median relative force error (%)");
  compressionView_ = makeView(compressionWidget_, compressionChart_, "Compression against error",
                              "compression rate", "relative error");
  hint_ = new QLabel(tr("Run a sweep (Tools > Sweep) or export a report to fill the charts; click a "
                        "haptic-box point to load that configuration."));
  hint_->setWordWrap(true);
  compressionNote_ = new QLabel(tr("Compression against error: no codec in this build (codec none); "
                                   "the chart fills once the codecs are merged."));
  compressionNote_->setWordWrap(true);
  compressionNote_->setAlignment(Qt::AlignCenter);
  compressionWidget_->hide();
  auto* charts = new QHBoxLayout;
  charts->addWidget(speedWidget_, 3);
  charts->addWidget(compressionWidget_, 2);
  charts->addWidget(compressionNote_, 2);
  auto* layout = new QVBoxLayout(this);
  layout->addWidget(hint_);
  layout->addLayout(charts, 1);
  setMinimumHeight(300);

  auto observer = vtkSmartPointer<vtkCallbackCommand>::New();
  observer->SetClientData(this);
  observer->SetCallback([](vtkObject*, unsigned long, void* self, void*) {
    static_cast<ChartsView*>(self)->onSelection();
  });
  // A left click on a point selects it (VTK's default is the right button); drag still pans.
  speedChart_->SetClickActionToButton(vtkChart::SELECT, vtkContextMouseEvent::LEFT_BUTTON);
  speedChart_->AddObserver(vtkCommand::SelectionChangedEvent, observer);
}

ChartsView::~ChartsView() = default;

void ChartsView::setRows(const std::vector<hb::SweepRow>& rows, const std::vector<std::pair<double, double>>& compression) {
  speedChart_->ClearPlots();
  boxRows_.clear();
  boxPlot_ = nullptr;
  std::vector<double> bx, by, ex, ey, lx, ly;
  for (const auto& r : rows) {
    const double x = std::log10(std::max(r.query_ns, 1.0));
    const double y = 100.0 * r.force_error_median;
    if (r.method == "haptic_box") {
      bx.push_back(x);
      by.push_back(y);
      boxRows_.push_back(r);
    } else if (r.method == "exact_embree") {
      ex.push_back(x);
      ey.push_back(y);
    } else {
      lx.push_back(x);
      ly.push_back(y);
    }
  }
  speedChart_->GetAxis(vtkAxis::BOTTOM)->SetTitle("log10 query time (ns)");
  if (!bx.empty()) boxPlot_ = addPoints(speedChart_, "haptic box (m, n)", bx, by, 255, 115, 0, VTK_MARKER_CIRCLE);
  if (!ex.empty()) addPoints(speedChart_, "exact Embree", ex, ey, 38, 191, 64, VTK_MARKER_DIAMOND);
  if (!lx.empty()) addPoints(speedChart_, "VTK static cell locator", lx, ly, 40, 90, 220, VTK_MARKER_SQUARE);
  speedChart_->RecalculateBounds();

  compressionChart_->ClearPlots();
  compressionWidget_->setVisible(!compression.empty());
  compressionNote_->setVisible(compression.empty());
  if (!compression.empty()) {
    std::vector<double> cx, cy;
    for (const auto& p : compression) {
      cx.push_back(p.first);
      cy.push_back(p.second);
    }
    addPoints(compressionChart_, "codec", cx, cy, 120, 40, 160, VTK_MARKER_CIRCLE);
    compressionChart_->SetTitle("Compression against error");
  } else {
    compressionChart_->SetTitle("Compression against error: no codec in this build (codec none)");
  }
  compressionChart_->RecalculateBounds();
  hint_->setText(rows.empty() ? hint_->text()
                              : tr("%1 rows; click a haptic-box point to load that configuration.").arg(rows.size()));
  speedWidget_->renderWindow()->Render();
  compressionWidget_->renderWindow()->Render();
}

void ChartsView::onSelection() {
  if (!boxPlot_) return;
  vtkIdTypeArray* sel = boxPlot_->GetSelection();
  if (!sel || sel->GetNumberOfTuples() == 0) return;
  choose(static_cast<std::size_t>(sel->GetValue(0)));
}

void ChartsView::choose(std::size_t index) {
  if (index >= boxRows_.size()) return;
  const hb::SweepRow& r = boxRows_[index];
  emit configurationChosen(r.m, r.n, QString::fromStdString(r.codec.empty() ? "none" : r.codec));
}
