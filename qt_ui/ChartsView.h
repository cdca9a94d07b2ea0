#pragma once
// The charts: speed against accuracy (sweep rows, with the exact Embree and VTK locator
// points; before any sweep, the bake's own points: the default bake, exact and the raw
// samplings it tried) and compression against error, in VTK chart views. Clicking a box
// configuration asks for it to be loaded.
#include "bake_chart_points.h"
#include "recipe/sweep.h"
#include <QWidget>
#include <vtkSmartPointer.h>
#include <string>
#include <utility>
#include <vector>

class QLabel;
class QVTKOpenGLNativeWidget;
class ChartPointLabels;
class vtkChartXY;
class vtkContextView;
class vtkPlot;

class ChartsView : public QWidget {
  Q_OBJECT
public:
  explicit ChartsView(QWidget* parent = nullptr);
  ~ChartsView() override;
  /// A sweep's (or a report's) rows; `notes`, when given, one per row: what the row is, in
  /// words, for its tooltip.
  void setRows(const std::vector<hb::SweepRow>& rows, const std::vector<std::pair<double, double>>& compression,
               const std::vector<std::string>& notes = {});
  /// The bake's own points before any sweep (hb::bake_chart_points): the default bake, exact
  /// and the raw samplings the bake tried, each labelled on the chart.
  void showBake(const std::vector<hb::BakeChartPoint>& points, const std::vector<std::pair<double, double>>& compression);
  /// Whether the speed chart shows a bake's own points (showBake), not a sweep's.
  bool showsBake() const { return showsBake_; }
  /// Whether it shows a sweep's or a report's rows (setRows).
  bool showsSweep() const { return !boxRows_.empty() && !showsBake_; }
  std::size_t pointCount() const { return boxRows_.size(); }
  /// The box rows shown (the samplings and the default bake, labelled; then the raw samplings
  /// a bake tried), in point order.
  const std::vector<hb::SweepRow>& boxRows() const { return boxRows_; }
  /// The words written beside points on the speed chart (the references, the default bake,
  /// the raw samplings a bake tried), and the budget line's.
  std::vector<std::string> speedPointLabels() const;
  std::string budgetLineLabel() const { return budgetLine_; }
  /// As a click on the box point `index` would do.
  void choose(std::size_t index);
  /// What the charts show (tests): the tooltip text of box point `index`, the x-axis tick
  /// labels, the legend's entries, whether a tooltip is on screen.
  std::string speedTooltip(std::size_t index) const;
  std::vector<std::string> speedAxisLabels() const;
  int legendEntries() const;
  bool tooltipVisible() const;
  /// The hint shown while the charts are empty, and the hint shown now.
  static QString emptyHint();
  /// A box baked to a budget before bakes timed what they tried (its file holds no query
  /// times): the hint says to bake it again; the charts are cleared.
  void showUntimedBake();
  static QString untimedBakeHint();
  QString hintText() const;

protected:
  bool eventFilter(QObject* watched, QEvent* event) override;

signals:
  void configurationChosen(int m, int n, const QString& codec);
  /// The default bake's point was clicked.
  void defaultBakeChosen();

private:
  void onSelection();
  void drawSpeed(const std::vector<hb::SweepRow>& rows, const std::vector<std::string>& notes);
  void drawCompression(const std::vector<std::pair<double, double>>& compression);

  QVTKOpenGLNativeWidget* speedWidget_;
  QVTKOpenGLNativeWidget* compressionWidget_;
  QLabel* hint_;
  QLabel* compressionNote_;
  vtkSmartPointer<vtkContextView> speedView_, compressionView_;
  vtkSmartPointer<vtkChartXY> speedChart_, compressionChart_;
  vtkSmartPointer<ChartPointLabels> labels_;
  vtkPlot* boxPlot_ = nullptr;
  vtkPlot* rawPlot_ = nullptr;   ///< the raw samplings a bake tried (after boxPlot_'s rows in boxRows_)
  std::size_t boxPlotRows_ = 0;  ///< boxRows_ in boxPlot_
  std::vector<hb::SweepRow> boxRows_;
  std::string budgetLine_;
  bool showsBake_ = false;
};
