#pragma once
// The scroll area a dock's panel sits in (MainWindow::createDocks): panels scroll inside their
// dock instead of being clipped or forcing the window taller than the screen.
#include <QEvent>
#include <QLayout>
#include <QResizeEvent>
#include <QScrollArea>
#include <QScrollBar>
#include <algorithm>

// A dock's scroll area: as wide as its panel wants (a plain QScrollArea asks for almost no
// width, and the dock collapses), as tall as the dock allows, scrolling vertically beyond.
class DockScrollArea : public QScrollArea {
public:
  QSize sizeHint() const override {
    const QSize panel = widget() ? widget()->sizeHint() : QSize(240, 200);
    return {panel.width() + verticalScrollBar()->sizeHint().width() + 2, std::min(panel.height(), 600)};
  }
  QSize minimumSizeHint() const override {
    const QSize panel = widget() ? widget()->minimumSizeHint() : QSize(200, 60);
    return {panel.width() + verticalScrollBar()->sizeHint().width() + 2, 60};
  }

protected:
  // A resizable scroll area ignores its panel's height-for-width: wrapped lines (the readout's)
  // were squeezed into one. The panel is kept as tall as its lines need at the viewport's width.
  void resizeEvent(QResizeEvent* event) override {
    QScrollArea::resizeEvent(event);
    fitHeight();
  }
  bool eventFilter(QObject* watched, QEvent* event) override {
    if (watched == widget() && event->type() == QEvent::LayoutRequest) fitHeight();
    return QScrollArea::eventFilter(watched, event);
  }

private:
  void fitHeight() {
    QWidget* panel = widget();
    if (!panel || !panel->layout() || !panel->layout()->hasHeightForWidth()) return;
    const int height = panel->layout()->totalHeightForWidth(viewport()->width());
    if (height > 0 && height != panel->minimumHeight()) panel->setMinimumHeight(height);
  }
};
