#pragma once
// The bake panel: the default recipe (as `hapticbox bake`) or, advanced, densities, pieces and
// codec; the cache; Bake and Cancel with a progress bar.
#include <QWidget>

class HapticSession;
class QCheckBox;
class QComboBox;
class QDoubleSpinBox;
class QLabel;
class QLineEdit;
class QProgressBar;
class QPushButton;
class QSpinBox;

class BakePanel : public QWidget {
  Q_OBJECT
public:
  explicit BakePanel(HapticSession* session, QWidget* parent = nullptr);

  /// Copies the controls into the session's settings.
  void applySettings();
  /// Shows the session's settings in the controls.
  void showSettings();
  QComboBox* recipeBox() const { return recipe_; }
  QPushButton* bakeButton() const { return bake_; }
  QPushButton* cancelButton() const { return cancel_; }
  QProgressBar* progressBar() const { return progress_; }
  QPushButton* clearCacheButton() const { return clearCache_; }
  QLabel* cacheLabel() const { return cacheInfo_; }

signals:
  void message(const QString& text);

private:
  void bake();
  void updateState();
  void browsePieces();
  void showCacheUsage();

  HapticSession* session_;
  QComboBox* recipe_;
  QSpinBox* m_;
  QSpinBox* n_;
  QDoubleSpinBox* padding_;
  QComboBox* pieces_;
  QLineEdit* piecesFile_;
  QPushButton* browse_;
  QComboBox* codec_;
  QCheckBox* refine_ = nullptr;
  QCheckBox* cache_;
  QLabel* cacheInfo_;
  QPushButton* clearCache_;
  QLabel* size_;
  QPushButton* bake_;
  QPushButton* cancel_;
  QProgressBar* progress_;
  QLabel* info_;
  bool bakeRunning_ = false;
};
