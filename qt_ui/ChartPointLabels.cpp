// 1. Map data to scene pixels with the bottom and left axes' ends (Point1, Point2) and ranges.
// 2. The legend's box is kept free; the line's words first (right end, above the line; the
//    line itself kept free), then each label: right of its point, else left, each at the
//    point's height, then a line above or below, the first place that covers no earlier text
//    and stays inside the axes.
#include "ChartPointLabels.h"
#include <vtkAxis.h>
#include <vtkChartLegend.h>
#include <vtkChartXY.h>
#include <vtkContext2D.h>
#include <vtkObjectFactory.h>
#include <vtkTextProperty.h>
#include <algorithm>

vtkStandardNewMacro(ChartPointLabels);

void ChartPointLabels::setLabels(std::vector<Label> labels) {
  labels_ = std::move(labels);
  Modified();
}

void ChartPointLabels::setLineLabel(double y, const std::string& text, unsigned char r, unsigned char g, unsigned char b) {
  line_ = Label{0.0, y, text, r, g, b};
  hasLine_ = !text.empty();
  Modified();
}

bool ChartPointLabels::Paint(vtkContext2D* painter) {
  drawn_ = 0;
  if (!chart_ || !chart_->GetVisible()) return true;
  vtkAxis* xa = chart_->GetAxis(vtkAxis::BOTTOM);
  vtkAxis* ya = chart_->GetAxis(vtkAxis::LEFT);
  const float* x1 = xa->GetPoint1();
  const float* x2 = xa->GetPoint2();
  const float* y1 = ya->GetPoint1();
  const float* y2 = ya->GetPoint2();
  const double xmin = xa->GetMinimum(), xmax = xa->GetMaximum(), ymin = ya->GetMinimum(), ymax = ya->GetMaximum();
  if (!(xmax > xmin) || !(ymax > ymin) || !(x2[0] > x1[0]) || !(y2[1] > y1[1])) return true;
  const auto sx = [&](double v) { return float(x1[0] + (v - xmin) / (xmax - xmin) * (x2[0] - x1[0])); };
  const auto sy = [&](double v) { return float(y1[1] + (v - ymin) / (ymax - ymin) * (y2[1] - y1[1])); };
  const float left = x1[0], right = x2[0], bottom = y1[1], top = y2[1];
  struct Box { float x0, x1, y0, y1; };
  std::vector<Box> taken;
  const auto isFree = [&](const Box& b) {
    if (b.x0 < left || b.x1 > right || b.y0 < bottom || b.y1 > top) return false;
    for (const Box& t : taken)
      if (b.x0 < t.x1 && t.x0 < b.x1 && b.y0 < t.y1 && t.y0 < b.y1) return false;
    return true;
  };
  vtkTextProperty* text = painter->GetTextProp();
  text->SetFontSize(12);
  text->SetBold(false);
  text->SetJustificationToLeft();
  text->SetVerticalJustificationToBottom();
  float bounds[4];
  if (hasLine_ && line_.y >= ymin && line_.y <= ymax) {
    text->SetColor(line_.r / 255.0, line_.g / 255.0, line_.b / 255.0);
    painter->ComputeStringBounds(line_.text.c_str(), bounds);
    const float x = right - 4.f - bounds[2], y = sy(line_.y) + 3.f;
    painter->DrawString(x, y, line_.text);
    taken.push_back({x, x + bounds[2], y, y + bounds[3]});
    taken.push_back({left, right, y - 5.f, y - 1.f});  // the line itself: no words across it
  }
  // The legend's box (scene pixels, as the chart lays it out) and every point's own mark are
  // kept clear of the words.
  if (chart_->GetShowLegend() && chart_->GetLegend() && chart_->GetLegend()->GetVisible()) {
    const vtkRectf r = chart_->GetLegend()->GetBoundingRect(painter);
    taken.push_back({r.GetX(), r.GetX() + r.GetWidth(), r.GetY(), r.GetY() + r.GetHeight()});
  }
  for (const Label& l : labels_) {
    const float px = sx(l.x), py = sy(l.y);
    taken.push_back({px - 6.f, px + 6.f, py - 6.f, py + 6.f});
  }
  for (const Label& l : labels_) {
    const float px = sx(l.x), py = sy(l.y);
    if (px < left - 1.f || px > right + 1.f || py < bottom - 1.f || py > top + 1.f) continue;
    painter->ComputeStringBounds(l.text.c_str(), bounds);
    const float w = bounds[2], h = bounds[3];
    bool placed = false;
    Box at{};
    for (float dy : {-0.5f, 0.6f, -1.6f, 1.7f, -2.7f, 2.8f}) {
      for (bool onLeft : {false, true}) {
        const float x = onLeft ? px - 9.f - w : px + 9.f, y = py + dy * h;
        const Box b{x, x + w, y, y + h};
        if (isFree(b)) {
          at = b;
          placed = true;
          break;
        }
      }
      if (placed) break;
    }
    if (!placed) {
      // No free place: right of the point (or left at the right edge), over whatever is there.
      const float x = px + 9.f + w > right ? px - 9.f - w : px + 9.f;
      at = Box{x, x + w, py - 0.5f * h, py + 0.5f * h};
    }
    taken.push_back(at);
    text->SetColor(l.r / 255.0, l.g / 255.0, l.b / 255.0);
    painter->DrawString(at.x0, at.y0, l.text);
    ++drawn_;
  }
  return true;
}
