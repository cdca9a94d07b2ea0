#include "ScreenshotDialog.h"
#include <QCheckBox>
#include <QDialogButtonBox>
#include <QFormLayout>
#include <QLabel>
#include <QPushButton>
#include <QSpinBox>
#include <QVBoxLayout>

ScreenshotDialog::ScreenshotDialog(const QSize& viewPixels, QWidget* parent)
    : QDialog(parent), view_(viewPixels), magnification_(new QSpinBox), transparent_(new QCheckBox), size_(new QLabel) {
  setWindowTitle(tr("Screenshot"));
  magnification_->setRange(1, 8);
  magnification_->setSuffix(tr(" x the view"));
  magnification_->setToolTip(tr("The image is this many times the view's width and height (text keeps its pixel size)"));
  transparent_->setText(tr("Transparent background"));
  transparent_->setToolTip(tr("PNG with an alpha channel: the background is left out, for slides and papers"));
  auto* form = new QFormLayout;
  form->addRow(tr("Resolution"), magnification_);
  form->addRow(QString(), size_);
  form->addRow(QString(), transparent_);
  auto* buttons = new QDialogButtonBox(QDialogButtonBox::Ok | QDialogButtonBox::Cancel);
  buttons->button(QDialogButtonBox::Ok)->setText(tr("Save As..."));
  connect(buttons, &QDialogButtonBox::accepted, this, &QDialog::accept);
  connect(buttons, &QDialogButtonBox::rejected, this, &QDialog::reject);
  auto* layout = new QVBoxLayout(this);
  layout->addLayout(form);
  layout->addWidget(buttons);
  connect(magnification_, QOverload<int>::of(&QSpinBox::valueChanged), this, &ScreenshotDialog::updateSize);
  updateSize();
}

int ScreenshotDialog::magnification() const { return magnification_->value(); }
void ScreenshotDialog::setMagnification(int m) { magnification_->setValue(m); }
bool ScreenshotDialog::transparent() const { return transparent_->isChecked(); }
void ScreenshotDialog::setTransparent(bool on) { transparent_->setChecked(on); }
QSize ScreenshotDialog::imagePixels() const { return view_ * magnification_->value(); }

void ScreenshotDialog::updateSize() {
  const QSize s = imagePixels();
  size_->setText(tr("%1 x %2 pixels").arg(s.width()).arg(s.height()));
}
