#include "DevicePanel.h"
#include <QComboBox>
#include <QFileDialog>
#include <QFormLayout>
#include <QHBoxLayout>
#include <QLabel>
#include <QLineEdit>
#include <QMessageBox>
#include <QPushButton>
#include <QSlider>
#include <cmath>

DevicePanel::DevicePanel(HapticSession* session, QWidget* parent) : QWidget(parent), session_(session) {
  kind_ = new QComboBox;
  kind_->addItem(tr("Virtual (mouse)"), int(DeviceKind::Virtual));
  kind_->addItem(tr("Replay a recorded trajectory"), int(DeviceKind::Replay));
  kind_->addItem(tr("Novint Falcon"), int(DeviceKind::Falcon));
  replay_ = new QLineEdit;
  replay_->setPlaceholderText(tr("servo log (.hblog)"));
  browse_ = new QPushButton(tr("..."));
  browse_->setMaximumWidth(32);
  auto* row = new QHBoxLayout;
  row->setContentsMargins(0, 0, 0, 0);
  row->addWidget(replay_);
  row->addWidget(browse_);
  apply_ = new QPushButton(tr("Use this device"));
  law_ = new QComboBox;
  law_->addItem(tr("Penalty (depth law)"), int(hb::ContactLaw::penalty));
  law_->addItem(tr("Proxy (god-object)"), int(hb::ContactLaw::proxy));
  law_->setToolTip(tr("How the servo turns answers into forces (hapticbox servo --law): the proxy holds "
                      "the tip on the surface and stays calm in crisp creases; a change restarts the servo"));
  depth_ = new QSlider(Qt::Horizontal);
  depth_->setRange(-50, 100);  // thousandths of the diagonal
  depth_->setToolTip(tr("Tip depth past the surface point (also Ctrl+wheel, [ and ])"));
  depthLabel_ = new QLabel;
  auto* tilt = new QPushButton(tr("Tilt probe (T)"));
  status_ = new QLabel;
  status_->setWordWrap(true);

  auto* form = new QFormLayout(this);
  form->addRow(tr("Device"), kind_);
  form->addRow(tr("Log"), row);
  form->addRow(apply_);
  form->addRow(tr("Contact law"), law_);
  form->addRow(tr("Depth"), depth_);
  form->addRow(QString(), depthLabel_);
  form->addRow(tilt);
  form->addRow(status_);

  connect(apply_, &QPushButton::clicked, this, &DevicePanel::applyDevice);
  connect(law_, qOverload<int>(&QComboBox::currentIndexChanged), this,
          [this] { session_->setContactLaw(static_cast<hb::ContactLaw>(law_->currentData().toInt())); });
  connect(tilt, &QPushButton::clicked, this, &DevicePanel::tiltRequested);
  connect(browse_, &QPushButton::clicked, this, [this] {
    const QString p = QFileDialog::getOpenFileName(this, tr("Servo log"), QString(), tr("Servo logs (*.hblog);;All files (*)"));
    if (!p.isEmpty()) {
      replay_->setText(p);
      kind_->setCurrentIndex(kind_->findData(int(DeviceKind::Replay)));
    }
  });
  connect(depth_, &QSlider::valueChanged, this, [this](int v) {
    session_->setDepthFraction(v / 1000.0);
    showDepth();
  });
  connect(session_, &HapticSession::deviceChanged, status_, &QLabel::setText);
  showDepth();
}

void DevicePanel::showDepth() {
  const int v = static_cast<int>(std::lround(session_->depthFraction() * 1000.0));
  if (depth_->value() != v) {
    const QSignalBlocker block(depth_);
    depth_->setValue(v);
  }
  depthLabel_->setText(tr("%1 % of the diagonal (%2 model units)")
                           .arg(session_->depthFraction() * 100.0, 0, 'f', 1)
                           .arg(session_->depthFraction() * session_->diagonal(), 0, 'g', 3));
}

void DevicePanel::applyDevice() {
  const auto kind = static_cast<DeviceKind>(kind_->currentData().toInt());
  QString note;
  if (!session_->setDevice(kind, replay_->text(), &note)) {
    kind_->setCurrentIndex(kind_->findData(int(session_->deviceKind())));
    // No hardware: say so once, then keep to the status line.
    if (!hardwareNoteShown_ && kind == DeviceKind::Falcon && isVisible()) {
      hardwareNoteShown_ = true;
      QMessageBox::information(this, tr("No Falcon"), note);
    }
    emit message(note);
  }
}
