#pragma once

#include <QDialog>

#include "core/Refusal.h"
#include "sim/TerrainFamilies.h"

class QButtonGroup;
class QComboBox;
class QDialogButtonBox;
class QLabel;
class QLineEdit;
class QSpinBox;

namespace ambler::widgets {

// What the station talks to: the built-in simulator (the default), a
// rover or ambler-sim over DDS, or a mission log to replay.
struct ConnectChoice {
  enum class Source { kSimulator, kDds, kLog };
  Source source = Source::kSimulator;
  quint64 seed = 1;                                         // simulator: its ground's seed
  sim::TerrainFamily family = sim::TerrainFamily::kCourse;  // simulator: its ground
  bool on_terrain_model = false;  // simulator: launched on a DTM, no family to choose
  int domain = 0;        // DDS domain id
  quint32 rover_id = 1;  // DDS: which rover
  QString key_file;      // DDS: this operator's key (docs/link.md)
  QString log_file;      // log: the mission log
};

// The Connect dialog: one choice at a time, its fields checked
// before OK is enabled, with the reason shown when it is not.
class ConnectDialog : public QDialog {
  Q_OBJECT

 public:
  explicit ConnectDialog(const ConnectChoice& initial, QWidget* parent = nullptr);

  ConnectChoice choice() const;
  void setChoice(const ConnectChoice& choice);
  // Refused, with why, when the choice cannot be used.
  Refusal problem() const;

 private:
  void check();

  QButtonGroup* sources_;
  QSpinBox* seed_;
  QComboBox* family_;
  bool on_terrain_model_ = false;
  QSpinBox* domain_;
  QSpinBox* rover_id_;
  QLineEdit* key_file_;
  QLineEdit* log_file_;
  QLabel* problem_;
  QDialogButtonBox* buttons_;
};

}  // namespace ambler::widgets
