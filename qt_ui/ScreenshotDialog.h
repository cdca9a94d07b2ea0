#pragma once
// The screenshot options ParaView offers: a resolution (a whole multiple of the view's size)
// and a transparent background.
#include <QDialog>
#include <QSize>

class QCheckBox;
class QLabel;
class QSpinBox;

class ScreenshotDialog : public QDialog {
  Q_OBJECT
public:
  /// `viewPixels`: the view's size, what magnification 1 writes.
  explicit ScreenshotDialog(const QSize& viewPixels, QWidget* parent = nullptr);

  int magnification() const;
  void setMagnification(int m);
  bool transparent() const;
  void setTransparent(bool on);
  /// The size of the image the options give, pixels.
  QSize imagePixels() const;
  QLabel* sizeLabel() const { return size_; }

private:
  void updateSize();

  QSize view_;
  QSpinBox* magnification_;
  QCheckBox* transparent_;
  QLabel* size_;
};
