#include "ChartsView.h"
#include "series_colours.h"
#include <array>
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
#include <QEvent>
#include <vtkTooltipItem.h>
#include "figure_text.h"

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
                   unsigned char r, unsigned char g, unsigned char b, int marker,
                   const std::vector<std::string>& tooltips = {}) {
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
  // The tooltip names the point in words ("m32 n16 none: 3.1 us, 0.0015 %"), not plot coordinates.
  if (tooltips.size() == xs.size() && !tooltips.empty()) {
    auto labels = vtkSmartPointer<vtkStringArray>::New();
    for (const std::string& t : tooltips) labels->InsertNextValue(t);
    plot->SetIndexedLabels(labels);
    plot->SetTooltipLabelFormat("%i");
  }
  return plot;
}

}  // namespace

ChartsView::ChartsView(QWidget* parent) : QWidget(parent) {
  speedWidget_ = new QVTKOpenGLNativeWidget;
  compressionWidget_ = new QVTKOpenGLNativeWidget;
  speedView_ = makeView(speedWidget_, speedChart_, "Speed against what a hand feels", "query time (ns, log)",
                        "probes perceptibly different from exact (%)");
  compressionView_ = makeView(compressionWidget_, compressionChart_, "Compression against error",
                              "compression rate (x : 1)", "median force error against raw tables (fraction)");
  hint_ = new QLabel(emptyHint());
  hint_->setWordWrap(true);
  compressionNote_ = new QLabel(tr("Compression against error: no curve yet. In the Bake panel choose Recipe "
                                   "Advanced with Codec none, bake, then File > Export Error Report: the curves of "
                                   "the codecs' error bounds appear here."));
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
  setMinimumHeight(180);  // a dock below the view: small enough for a 768-pixel screen

  auto observer = vtkSmartPointer<vtkCallbackCommand>::New();
  observer->SetClientData(this);
  observer->SetCallback([](vtkObject*, unsigned long, void* self, void*) {
    static_cast<ChartsView*>(self)->onSelection();
  });
  // A left click on a point selects it (VTK's default is the right button); drag still pans.
  speedChart_->SetClickActionToButton(vtkChart::SELECT, vtkContextMouseEvent::LEFT_BUTTON);
  speedChart_->AddObserver(vtkCommand::SelectionChangedEvent, observer);
  // VTK hides a chart's tooltip on its own mouse moves only: hide it when the mouse leaves.
  speedWidget_->installEventFilter(this);
  compressionWidget_->installEventFilter(this);
}

bool ChartsView::eventFilter(QObject* watched, QEvent* event) {
  if (event->type() == QEvent::Leave) {
    for (auto [widget, chart] : {std::pair<QObject*, vtkChartXY*>{speedWidget_, speedChart_},
                                 std::pair<QObject*, vtkChartXY*>{compressionWidget_, compressionChart_}})
      if (watched == widget && chart->GetTooltip() && chart->GetTooltip()->GetVisible()) {
        chart->GetTooltip()->SetVisible(false);
        static_cast<QVTKOpenGLNativeWidget*>(widget)->renderWindow()->Render();
      }
  }
  return QWidget::eventFilter(watched, event);
}

bool ChartsView::tooltipVisible() const { return speedChart_->GetTooltip() && speedChart_->GetTooltip()->GetVisible(); }

std::string ChartsView::speedTooltip(std::size_t index) const {
  if (!boxPlot_ || !boxPlot_->GetIndexedLabels() || vtkIdType(index) >= boxPlot_->GetIndexedLabels()->GetNumberOfValues())
    return {};
  return std::string(boxPlot_->GetTooltipLabel(vtkVector2d(0, 0), vtkIdType(index), 0));
}

std::vector<std::string> ChartsView::speedAxisLabels() const {
  std::vector<std::string> out;
  vtkStringArray* labels = speedChart_->GetAxis(vtkAxis::BOTTOM)->GetTickLabels();
  for (vtkIdType i = 0; labels && i < labels->GetNumberOfValues(); ++i) out.push_back(labels->GetValue(i));
  return out;
}

int ChartsView::legendEntries() const { return speedChart_->GetShowLegend() ? int(speedChart_->GetNumberOfPlots()) : 0; }

ChartsView::~ChartsView() = default;

QString ChartsView::emptyHint() {
  return tr("Run a sweep (Tools > Run Sweep) or export a report (File > Export Error Report) to fill the charts; "
            "click a haptic-box point to load that configuration.");
}

void ChartsView::setRows(const std::vector<hb::SweepRow>& rows, const std::vector<std::pair<double, double>>& compression) {
  speedChart_->ClearPlots();
  boxRows_.clear();
  boxPlot_ = nullptr;
  std::vector<double> bx, by, ex, ey, lx, ly;
  for (const auto& r : rows) {
    const double x = std::log10(std::max(r.query_ns, 1.0));
    // The headline: the share of probes a hand would tell apart (hapticbox sweep's felt_%).
    const double y = 100.0 * r.perceptible_share;
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
  // The x axis is log10 of the time; its ticks are labelled with real times (1, 2, 5 per decade).
  vtkAxis* xAxis = speedChart_->GetAxis(vtkAxis::BOTTOM);
  xAxis->SetTitle("query time (log scale)");
  double lo = 1e300, hi = -1e300;
  for (const auto* v : {&bx, &ex, &lx})
    for (double x : *v) lo = std::min(lo, x), hi = std::max(hi, x);
  if (lo <= hi) {
    lo = std::floor(lo - 0.1);
    hi = std::ceil(hi + 0.1);
    auto positions = vtkSmartPointer<vtkDoubleArray>::New();
    auto labels = vtkSmartPointer<vtkStringArray>::New();
    for (int decade = int(lo); decade <= int(hi); ++decade)
      for (double step : {1.0, 2.0, 5.0}) {
        const double t = std::log10(step) + decade;
        if (t < lo - 1e-9 || t > hi + 1e-9) continue;
        positions->InsertNextValue(t);
        labels->InsertNextValue(hb::duration_text(step * std::pow(10.0, decade) * 1e-9));
      }
    xAxis->SetBehavior(vtkAxis::FIXED);
    xAxis->SetRange(lo, hi);
    xAxis->SetCustomTickPositions(positions, labels);
  }
  auto tip = [](const hb::SweepRow& r) {
    std::string t = r.method == "haptic_box" && !r.label.empty() ? r.label + ", " + (r.codec.empty() ? std::string("none") : r.codec)
                    : r.method == "haptic_box" ? "m " + std::to_string(r.m) + ", n " + std::to_string(r.n) + ", " +
                                                   (r.codec.empty() ? std::string("none") : r.codec) + (r.refine ? ", refined" : "")
                                             : r.method;
    return t + ": " + hb::duration_text(r.query_ns * 1e-9) + " a query, perceptibly different on " +
           hb::percent(r.perceptible_share) + " of the probes (median error " + hb::percent(r.force_error_median) +
           ", agreement " + hb::agreement_percent(r.contact_agreement) + ")";
  };
  std::vector<std::string> bt, et, lt;
  for (const auto& r : rows) (r.method == "haptic_box" ? bt : r.method == "exact_embree" ? et : lt).push_back(tip(r));
  // Only the series present get a plot (and so a legend entry), in the series colours
  // (series_colours.h, as the report's charts and the 3D arrows): box blue, exact red, VTK orange.
  const auto c = [](const hb::SeriesColour& s) { return std::array<unsigned char, 3>{(unsigned char)s.r, (unsigned char)s.g, (unsigned char)s.b}; };
  const auto box = c(hb::kBoxSeries), exact = c(hb::kExactSeries), vtk = c(hb::kVtkSeries);
  if (!bx.empty()) boxPlot_ = addPoints(speedChart_, "haptic box", bx, by, box[0], box[1], box[2], VTK_MARKER_CIRCLE, bt);
  if (!ex.empty()) addPoints(speedChart_, "exact Embree", ex, ey, exact[0], exact[1], exact[2], VTK_MARKER_DIAMOND, et);
  if (!lx.empty()) addPoints(speedChart_, "VTK static cell locator", lx, ly, vtk[0], vtk[1], vtk[2], VTK_MARKER_SQUARE, lt);
  speedChart_->SetShowLegend(!rows.empty());
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
    std::vector<std::string> ct;
    for (const auto& p : compression)
      ct.push_back(hb::sig(p.first) + ":1, median error " + hb::percent(p.second) + " against the raw tables");
    addPoints(compressionChart_, "codec error bounds", cx, cy, 120, 40, 160, VTK_MARKER_CIRCLE, ct);
    compressionChart_->SetTitle("Compression against error");
  } else {
    compressionChart_->SetTitle("Compression against error: no curve yet");
  }
  compressionChart_->RecalculateBounds();
  hint_->setText(rows.empty() ? emptyHint()
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
  if (!r.label.empty()) emit defaultBakeChosen();  // the default bake's row: its recipe, not one sampling
  else emit configurationChosen(r.m, r.n, QString::fromStdString(r.codec.empty() ? "none" : r.codec));
}

QString ChartsView::hintText() const { return hint_->text(); }
