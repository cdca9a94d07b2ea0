#pragma once
// The charts: speed against accuracy (sweep rows, with the exact Embree and VTK locator
// points) and compression against error, in VTK chart views. Clicking a box configuration
// asks for it to be loaded.
#include "recipe/sweep.h"
#include <QWidget>
#include <vtkSmartPointer.h>
#include <string>
#include <utility>
#include <vector>

class QLabel;
class QVTKOpenGLNativeWidget;
class vtkChartXY;
class vtkContextView;
class vtkPlot;

class ChartsView : public QWidget {
  Q_OBJECT
public:
  explicit ChartsView(QWidget* parent = nullptr);
  ~ChartsView() override;
  void setRows(const std::vector<hb::SweepRow>& rows, const std::vector<std::pair<double, double>>& compression);
  std::size_t pointCount() const { return boxRows_.size(); }
  /// The box rows shown (the samplings and the default bake, labelled), in point order.
  const std::vector<hb::SweepRow>& boxRows() const { return boxRows_; }
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
  QString hintText() const;

protected:
  bool eventFilter(QObject* watched, QEvent* event) override;

signals:
  void configurationChosen(int m, int n, const QString& codec);
  /// The default bake's point was clicked.
  void defaultBakeChosen();

private:
  void onSelection();

  QVTKOpenGLNativeWidget* speedWidget_;
  QVTKOpenGLNativeWidget* compressionWidget_;
  QLabel* hint_;
  QLabel* compressionNote_;
  vtkSmartPointer<vtkContextView> speedView_, compressionView_;
  vtkSmartPointer<vtkChartXY> speedChart_, compressionChart_;
  vtkPlot* boxPlot_ = nullptr;
  std::vector<hb::SweepRow> boxRows_;
};
