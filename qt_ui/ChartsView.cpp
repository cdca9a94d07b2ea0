#include "ChartsView.h"
#include "ChartPointLabels.h"
#include "series_colours.h"
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
#include <vtkPen.h>
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
                        "perceptibly different probes (%)");  // as the report's chart
  labels_ = vtkSmartPointer<ChartPointLabels>::New();
  labels_->setChart(speedChart_);
  speedView_->GetScene()->AddItem(labels_);  // after the chart: drawn over it
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
  // boxRows_: boxPlot_'s rows, then rawPlot_'s.
  vtkPlot* plot = index < boxPlotRows_ ? boxPlot_ : rawPlot_;
  if (index >= boxPlotRows_) index -= boxPlotRows_;
  if (!plot || !plot->GetIndexedLabels() || vtkIdType(index) >= plot->GetIndexedLabels()->GetNumberOfValues())
    return {};
  return std::string(plot->GetTooltipLabel(vtkVector2d(0, 0), vtkIdType(index), 0));
}

std::vector<std::string> ChartsView::speedAxisLabels() const {
  std::vector<std::string> out;
  vtkStringArray* labels = speedChart_->GetAxis(vtkAxis::BOTTOM)->GetTickLabels();
  for (vtkIdType i = 0; labels && i < labels->GetNumberOfValues(); ++i) out.push_back(labels->GetValue(i));
  return out;
}

int ChartsView::legendEntries() const {
  if (!speedChart_->GetShowLegend()) return 0;
  int entries = 0;
  for (vtkIdType i = 0; i < speedChart_->GetNumberOfPlots(); ++i) entries += speedChart_->GetPlot(i)->GetLegendVisibility() ? 1 : 0;
  return entries;
}

ChartsView::~ChartsView() = default;

QString ChartsView::emptyHint() {
  return tr("Run a sweep (Tools > Run Sweep) or export a report (File > Export Error Report) to fill the charts; "
            "click a haptic-box point to load that configuration.");
}

QString ChartsView::untimedBakeHint() {
  return tr("This box file was baked by an older version, before bakes timed what they tried, so there is nothing to chart: "
            "bake the model again (Bake) to see the default bake, exact and the raw samplings it tried, or run a "
            "sweep (Tools > Run Sweep).");
}

void ChartsView::showUntimedBake() {
  setRows({}, {});
  hint_->setText(untimedBakeHint());
}

void ChartsView::setRows(const std::vector<hb::SweepRow>& rows, const std::vector<std::pair<double, double>>& compression,
                         const std::vector<std::string>& notes) {
  showsBake_ = false;
  drawSpeed(rows, notes);
  drawCompression(compression);
  hint_->setText(rows.empty() ? emptyHint()
                              : tr("%1 rows; click a haptic-box point to load that configuration.").arg(rows.size()));
  speedWidget_->renderWindow()->Render();
  compressionWidget_->renderWindow()->Render();
}

void ChartsView::showBake(const std::vector<hb::BakeChartPoint>& points,
                          const std::vector<std::pair<double, double>>& compression) {
  std::vector<hb::SweepRow> rows;
  std::vector<std::string> notes;
  for (const hb::BakeChartPoint& p : points) {
    rows.push_back(p.row);
    notes.push_back(p.about);
  }
  setRows(rows, compression, notes);
  showsBake_ = !rows.empty();
  if (showsBake_)
    hint_->setText(tr("The bake's own figures, timed when it baked: the default bake, exact and the raw samplings it "
                      "tried (hover a point for what it is). Tools > Run Sweep adds samplings; click the default bake "
                      "to load it again."));
}

namespace {

// A point's tooltip: what it is, its time, what a hand feels, its errors.
std::string rowTooltip(const hb::SweepRow& r) {
  const std::string codec = r.codec.empty() ? std::string("none") : r.codec;
  const std::string t = r.method == "haptic_box" && !r.label.empty() ? r.label + ", " + codec
                        : r.method == "haptic_box" ? "m " + std::to_string(r.m) + ", n " + std::to_string(r.n) + ", " + codec +
                                                       (r.refine ? ", refined" : "")
                                                   : r.method;
  std::string tip = t + ": " + hb::duration_text(r.query_ns * 1e-9) + " a query, perceptibly different on " +
                    hb::percent(r.perceptible_share) + " of the probes";
  if (r.contact_agreement >= 0.0)
    tip += " (median error " + hb::percent(r.force_error_median) + ", agreement " + hb::agreement_percent(r.contact_agreement) + ")";
  return tip;
}

// The words beside a point: references and named rows (the default bake, a raw sampling a
// bake tried); a sweep's samplings are many and say what they are in their tooltips.
std::string pointWords(const hb::SweepRow& r) {
  if (r.method == "exact_embree") return "exact Embree";
  if (r.method != "haptic_box") return "VTK locator";
  return r.label;
}

}  // namespace

void ChartsView::drawSpeed(const std::vector<hb::SweepRow>& rows, const std::vector<std::string>& notes) {
  speedChart_->ClearPlots();
  boxRows_.clear();
  boxPlot_ = rawPlot_ = nullptr;
  boxPlotRows_ = 0;
  budgetLine_.clear();
  struct Series {
    std::vector<double> x, y;
    std::vector<std::string> tips;
  };
  Series box, raw, exact, vtk;
  std::vector<hb::SweepRow> rawRows;
  std::vector<ChartPointLabels::Label> words;
  // Only the series present get a plot (and so a legend entry), in the series colours
  // (series_colours.h, as the report's charts and the 3D arrows): box blue, exact red, VTK
  // orange, the raw samplings a bake tried purple.
  const auto seriesOf = [](const hb::SweepRow& r) -> const hb::SeriesColour& {
    return r.tried_by_the_bake ? hb::kRawTrialSeries
           : r.method == "haptic_box"   ? hb::kBoxSeries
           : r.method == "exact_embree" ? hb::kExactSeries
                                        : hb::kVtkSeries;
  };
  // The report's axis (hb::felt_axis_cap_percent): a share above sits on the top edge, its
  // words saying its value; its tooltip keeps it.
  const double cap = hb::felt_axis_cap_percent();
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const hb::SweepRow& r = rows[i];
    const double x = std::log10(std::max(r.query_ns, 1.0));
    // The headline: the share of probes a hand would tell apart (hapticbox sweep's felt_%).
    const double y = std::min(100.0 * r.perceptible_share, hb::felt_axis_edge_percent());
    const bool rawTrial = r.tried_by_the_bake;
    Series& s = rawTrial ? raw : r.method == "haptic_box" ? box : r.method == "exact_embree" ? exact : vtk;
    s.x.push_back(x);
    s.y.push_back(y);
    s.tips.push_back(i < notes.size() && !notes[i].empty() ? notes[i] : rowTooltip(r));
    if (rawTrial) rawRows.push_back(r);
    else if (r.method == "haptic_box") boxRows_.push_back(r);
    std::string w = pointWords(r);
    if (!w.empty()) w += hb::off_scale_words(r.perceptible_share);
    if (!w.empty()) {
      const hb::SeriesColour& c = seriesOf(r);
      words.push_back({x, y, w, (unsigned char)c.r, (unsigned char)c.g, (unsigned char)c.b});
    }
  }
  boxPlotRows_ = boxRows_.size();
  boxRows_.insert(boxRows_.end(), rawRows.begin(), rawRows.end());
  // The x axis is log10 of the time; its ticks are labelled with real times (1, 2, 5 per decade).
  vtkAxis* xAxis = speedChart_->GetAxis(vtkAxis::BOTTOM);
  xAxis->SetTitle("query time (log scale)");
  double lo = 1e300, hi = -1e300;
  for (const Series* v : {&box, &raw, &exact, &vtk})
    for (double x : v->x) lo = std::min(lo, x), hi = std::max(hi, x);
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
    // The default budget's share, a dashed green line across with its words (as the report's).
    const double budget = 100.0 * hb::ErrorBudget{}.perceptible;
    vtkPlot* line = speedChart_->AddPlot(vtkChart::LINE);
    auto table = vtkSmartPointer<vtkTable>::New();
    for (const char* name : {"x", "default budget"}) {
      auto column = vtkSmartPointer<vtkDoubleArray>::New();
      column->SetName(name);
      table->AddColumn(column);
    }
    table->SetNumberOfRows(2);
    table->SetValue(0, 0, lo), table->SetValue(0, 1, budget);
    table->SetValue(1, 0, hi), table->SetValue(1, 1, budget);
    line->SetInputData(table, 0, 1);
    line->SetColor(44, 160, 44, 255);
    line->SetWidth(1.5);
    line->GetPen()->SetLineType(vtkPen::DASH_LINE);
    line->SetLegendVisibility(false);
    line->SetSelectable(false);
    budgetLine_ = "default budget: at most " + hb::sig(budget) + " % perceptibly different";
    labels_->setLineLabel(budget, budgetLine_, 44, 160, 44);
  } else {
    labels_->setLineLabel(0.0, "", 0, 0, 0);
  }
  labels_->setLabels(words);
  // Room above the top edge for its words, and the budget's line in view (as the report's).
  const double ymax = cap;
  vtkAxis* yAxis = speedChart_->GetAxis(vtkAxis::LEFT);
  yAxis->SetBehavior(vtkAxis::FIXED);
  yAxis->SetRange(-0.04 * ymax, 1.15 * ymax);
  const auto add = [&](const char* name, const Series& s, const hb::SeriesColour& c, int marker) -> vtkPlot* {
    if (s.x.empty()) return nullptr;
    return addPoints(speedChart_, name, s.x, s.y, (unsigned char)c.r, (unsigned char)c.g, (unsigned char)c.b, marker, s.tips);
  };
  boxPlot_ = add("haptic box", box, hb::kBoxSeries, VTK_MARKER_CIRCLE);
  rawPlot_ = add("raw box, tried by the bake", raw, hb::kRawTrialSeries, VTK_MARKER_CROSS);
  add("exact Embree", exact, hb::kExactSeries, VTK_MARKER_DIAMOND);
  add("VTK static cell locator", vtk, hb::kVtkSeries, VTK_MARKER_SQUARE);
  speedChart_->SetShowLegend(!rows.empty());
  speedChart_->RecalculateBounds();
}

void ChartsView::drawCompression(const std::vector<std::pair<double, double>>& compression) {
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
  // A raw sampling a bake tried is one box over the whole model, which no window bake makes:
  // its tooltip says what it is, a click loads nothing.
  if (r.tried_by_the_bake) return;
  if (!r.label.empty()) emit defaultBakeChosen();  // the default bake's row: its recipe, not one sampling
  else emit configurationChosen(r.m, r.n, QString::fromStdString(r.codec.empty() ? "none" : r.codec));
}

std::vector<std::string> ChartsView::speedPointLabels() const {
  std::vector<std::string> out;
  for (const ChartPointLabels::Label& l : labels_->labels()) out.push_back(l.text);
  return out;
}

QString ChartsView::hintText() const { return hint_->text(); }
