// Widget test of the event and command table as a walk adds and answers
// rows; needs a display (xvfb-run).
#include <QApplication>
#include <QItemSelectionModel>
#include <QtTest/QtTest>
#include <vector>

#include "widgets/CommandLogView.h"

using ambler::replay::LogRow;
using ambler::widgets::CommandLogView;

class CommandLogViewTest : public QObject {
  Q_OBJECT

 private slots:
  // A command answered in place and a new row appended: the operator's
  // selection stays where it was (a model reset would clear it).
  void answersAndNewRowsKeepTheOperatorsSelection() {
    CommandLogView view;
    view.resize(800, 300);
    view.show();
    QVERIFY(QTest::qWaitForWindowExposed(&view));
    std::vector<LogRow> rows = {{10.0, "alice", "LegMove leg 2, 3 waypoints", "sent", ""},
                                {11.0, "alice", "BodyMove 0.50 m", "sent", ""}};
    view.setRows(rows);
    QCOMPARE(view.rowCount(), 2);
    view.selectRow(0);
    QVERIFY(view.selectionModel()->isRowSelected(0, {}));

    rows[1].outcome = "accepted";
    rows.push_back({12.0, "rover", "holds", "", "link lost for 3.0 s"});
    view.setRows(rows);
    QCOMPARE(view.rowCount(), 3);
    QCOMPARE(view.cellText(1, 3), QString("accepted"));
    QCOMPARE(view.cellText(2, 4), QString("link lost for 3.0 s"));
    QVERIFY(view.selectionModel()->isRowSelected(0, {}));

    // A shorter table (a new walk's) drops the rows beyond it.
    view.setRows({rows[0]});
    QCOMPARE(view.rowCount(), 1);
    QCOMPARE(view.cellText(0, 2), QString("LegMove leg 2, 3 waypoints"));
  }
};

int main(int argc, char** argv) {
  QApplication app(argc, argv);
  CommandLogViewTest test;
  return QTest::qExec(&test, argc, argv);
}

#include "CommandLogViewTest.moc"
