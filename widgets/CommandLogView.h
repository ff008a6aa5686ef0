#pragma once

#include <QAbstractTableModel>
#include <QTableView>
#include <optional>
#include <vector>

#include "replay/CommandTable.h"

namespace ambler::widgets {

// The event and command table: time (UTC), operator, command,
// the rover's answer and the reason, one row per command or decision.
// Refusals are red. In a replay, rows after the timeline's time are grey
// and the last row before it is kept in view.
class CommandLogView : public QTableView {
  Q_OBJECT

 public:
  explicit CommandLogView(QWidget* parent = nullptr);

  void setRows(const std::vector<replay::LogRow>& rows);
  // Rows after `time_s` are yet to come; none: every row has happened.
  void setCurrentTime(std::optional<double> time_s);
  int rowCount() const;
  QString cellText(int row, int column) const;
  // The whole table as CSV (RFC 4180: quoted where needed), times in
  // seconds since the epoch so nothing is lost.
  QString toCsv() const;

 private:
  class Model;
  Model* model_;
};

}  // namespace ambler::widgets
