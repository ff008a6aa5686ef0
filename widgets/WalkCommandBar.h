#pragma once

#include <QWidget>

class QComboBox;
class QDoubleSpinBox;
class QSpinBox;

namespace ambler::widgets {

// What the operator asks a walk to do: how many steps, along which path.
struct WalkCommand {
  enum class Path { kStraight, kArcLeft, kArcRight, kTurnLeft, kTurnRight };
  int steps = 5;
  Path path = Path::kStraight;
  double radius_m = 10.0;  // of an arc
};

// The walk's steps, path (straight, an arc to either side, a turn in
// place) and an arc's radius, beside the toolbar's Walk; the radius is
// editable for arcs only.
class WalkCommandBar : public QWidget {
  Q_OBJECT

 public:
  explicit WalkCommandBar(QWidget* parent = nullptr);

  WalkCommand command() const;
  void setCommand(const WalkCommand& command);

 private:
  QSpinBox* steps_;
  QComboBox* path_;
  QDoubleSpinBox* radius_;
};

}  // namespace ambler::widgets
