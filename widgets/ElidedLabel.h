#pragma once

#include <QLabel>

namespace ambler::widgets {

// A one-line label that, when its text is wider than itself, shows it cut
// in the middle with an ellipsis: the start says what happened and the end
// often names the file ("logging to /tmp/...-20261207T024435Z.sqlite").
// QLabel would cut the end off unmarked.
class ElidedLabel : public QLabel {
 public:
  using QLabel::QLabel;
  // The text as drawn at the label's current width.
  [[nodiscard]] QString shownText() const;

 protected:
  void paintEvent(QPaintEvent* e) override;
};

}  // namespace ambler::widgets
