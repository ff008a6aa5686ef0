#include "widgets/CommandLogView.h"

#include <QColor>
#include <QDateTime>
#include <QHeaderView>
#include <QRegularExpression>
#include <QTimeZone>
#include <algorithm>

namespace ambler::widgets {

namespace {

const QStringList kHeaders = {QObject::tr("Time (UTC)"), QObject::tr("Operator"),
                              QObject::tr("Command"), QObject::tr("Answer"), QObject::tr("Reason")};

QString clockTime(double time_s) {
  return QDateTime::fromMSecsSinceEpoch(qint64(std::llround(time_s * 1000.0)), QTimeZone::utc())
      .toString("hh:mm:ss.zzz");
}

QString csvField(QString text) {
  if (!text.contains(QRegularExpression("[\",\\n\\r]"))) return text;
  return '"' + text.replace('"', "\"\"") + '"';
}

}  // namespace

class CommandLogView::Model : public QAbstractTableModel {
 public:
  using QAbstractTableModel::QAbstractTableModel;

  int rowCount(const QModelIndex& parent = {}) const override {
    return parent.isValid() ? 0 : int(rows_.size());
  }
  int columnCount(const QModelIndex& parent = {}) const override {
    return parent.isValid() ? 0 : int(kHeaders.size());
  }
  QVariant headerData(int section, Qt::Orientation o, int role) const override {
    if (o == Qt::Horizontal && role == Qt::DisplayRole) return kHeaders.value(section);
    return {};
  }
  QVariant data(const QModelIndex& index, int role) const override {
    const auto& r = rows_[std::size_t(index.row())];
    if (role == Qt::DisplayRole || role == Qt::ToolTipRole) return text(r, index.column());
    if (role == Qt::ForegroundRole) {
      if (index.row() >= int(happened_)) return QColor(150, 150, 150);
      if (r.outcome == "refused" || r.outcome == "rejected" || r.what == "holds")
        return QColor(183, 28, 28);
    }
    return {};
  }
  static QString text(const replay::LogRow& r, int column) {
    switch (column) {
      case 0:
        return clockTime(r.time_s);
      case 1:
        return QString::fromStdString(r.who);
      case 2:
        return QString::fromStdString(r.what);
      case 3:
        return QString::fromStdString(r.outcome);
      default:
        return QString::fromStdString(r.reason);
    }
  }
  // Rows are answered in place and appended as a walk goes on: only the
  // rows that changed are announced, so the view keeps its selection and
  // scroll position and lays out only what is new.
  void setRows(const std::vector<replay::LogRow>& rows) {
    const std::size_t old_size = rows_.size(), common = std::min(old_size, rows.size());
    std::size_t first = 0;
    while (first < common && rows_[first] == rows[first]) ++first;
    if (rows.size() < old_size) {
      beginRemoveRows({}, int(rows.size()), int(old_size) - 1);
      rows_.resize(rows.size());
      endRemoveRows();
    }
    std::copy(rows.begin() + std::ptrdiff_t(first), rows.begin() + std::ptrdiff_t(common),
              rows_.begin() + std::ptrdiff_t(first));
    if (first < common)
      emit dataChanged(index(int(first), 0), index(int(common) - 1, columnCount() - 1));
    if (rows.size() > old_size) {
      beginInsertRows({}, int(old_size), int(rows.size()) - 1);
      rows_.insert(rows_.end(), rows.begin() + std::ptrdiff_t(old_size), rows.end());
      endInsertRows();
    }
    happened_ = rows_.size();
  }
  // Returns the number of rows that have happened by `time_s`.
  std::size_t setCurrentTime(std::optional<double> time_s) {
    const std::size_t happened =
        time_s ? std::size_t(std::upper_bound(
                                 rows_.begin(), rows_.end(), *time_s,
                                 [](double t, const replay::LogRow& r) { return t < r.time_s; }) -
                             rows_.begin())
               : rows_.size();
    if (happened != happened_) {
      happened_ = happened;
      if (!rows_.empty()) emit dataChanged(index(0, 0), index(rowCount() - 1, columnCount() - 1));
    }
    return happened_;
  }
  const std::vector<replay::LogRow>& rows() const { return rows_; }

 private:
  std::vector<replay::LogRow> rows_;
  std::size_t happened_ = 0;
};

CommandLogView::CommandLogView(QWidget* parent) : QTableView(parent), model_(new Model(this)) {
  setModel(model_);
  setAlternatingRowColors(true);
  setSelectionBehavior(QAbstractItemView::SelectRows);
  setEditTriggers(QAbstractItemView::NoEditTriggers);
  verticalHeader()->hide();
  horizontalHeader()->setStretchLastSection(true);
  horizontalHeader()->setSectionResizeMode(QHeaderView::Interactive);
  setColumnWidth(0, 100);
  setColumnWidth(1, 90);
  setColumnWidth(2, 260);
  setColumnWidth(3, 80);
}

void CommandLogView::setRows(const std::vector<replay::LogRow>& rows) {
  const bool at_end = rows.size() > std::size_t(model_->rowCount());
  model_->setRows(rows);
  if (at_end) scrollToBottom();
}

void CommandLogView::setCurrentTime(std::optional<double> time_s) {
  const auto happened = model_->setCurrentTime(time_s);
  if (happened > 0) scrollTo(model_->index(int(happened) - 1, 0));
}

int CommandLogView::rowCount() const { return model_->rowCount(); }

QString CommandLogView::cellText(int row, int column) const {
  return Model::text(model_->rows().at(std::size_t(row)), column);
}

QString CommandLogView::toCsv() const {
  QString csv = "time_s,operator,command,answer,reason\n";
  for (const auto& r : model_->rows()) {
    QStringList fields{QString::number(r.time_s, 'f', 3)};
    for (int column = 1; column < kHeaders.size(); ++column)
      fields << csvField(Model::text(r, column));
    csv += fields.join(',') + '\n';
  }
  return csv;
}

}  // namespace ambler::widgets
