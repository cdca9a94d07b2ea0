#pragma once
// Words beside chosen points of a vtkChartXY (the references, the default bake, the raw
// samplings a bake tried) and beside a horizontal line (the budget), placed at every paint from
// the chart's axes, so they follow resizing, panning and zooming. A label that would run past
// the plot's right edge goes left of its point; one that would cover another label moves up or
// down a line. Added to the chart's scene after the chart, so it is drawn on top.
#include <vtkContextItem.h>
#include <string>
#include <vector>

class vtkChartXY;

class ChartPointLabels : public vtkContextItem {
public:
  static ChartPointLabels* New();
  vtkTypeMacro(ChartPointLabels, vtkContextItem);

  /// A label for the point (x, y) in the chart's data units (the bottom and left axes).
  struct Label {
    double x = 0, y = 0;
    std::string text;
    unsigned char r = 0, g = 0, b = 0;
  };
  void setChart(vtkChartXY* chart) { chart_ = chart; }
  void setLabels(std::vector<Label> labels);
  /// Words at the right end of the horizontal line y = `y` (data units), above it.
  void setLineLabel(double y, const std::string& text, unsigned char r, unsigned char g, unsigned char b);
  const std::vector<Label>& labels() const { return labels_; }
  /// How many labels the last paint drew (inside the axes).
  int drawn() const { return drawn_; }

  bool Paint(vtkContext2D* painter) override;

protected:
  ChartPointLabels() = default;

private:
  ChartPointLabels(const ChartPointLabels&) = delete;
  void operator=(const ChartPointLabels&) = delete;

  vtkChartXY* chart_ = nullptr;
  std::vector<Label> labels_;
  Label line_;
  bool hasLine_ = false;
  int drawn_ = 0;
};
