// Widget test of the step-approval workflow (issue 7) against the
// simulator in this process: a proposal reaches the panel with its
// interlocks, Approve moves the rover, Reject sends nothing, and the
// auto-approve switch is visible when on. Needs a display (xvfb-run).
#include <QApplication>
#include <QCheckBox>
#include <QLabel>
#include <QPushButton>
#include <QTableWidget>
#include <QtTest/QtTest>

#include "app/gs/WalkSession.h"
#include "widgets/MapView.h"
#include "widgets/StepApprovalPanel.h"

using ambler::executive::Phase;
using ambler::gs::WalkSession;
using ambler::widgets::MapView;
using ambler::widgets::StepApprovalPanel;

namespace {

const ambler::walk::WalkConfig& config() {
  static const auto c = ambler::walk::readDefaultWalkConfig();
  return c;
}

// The panel wired to a session as the main window wires them.
struct Console {
  WalkSession session{config(), 1, "alice"};
  StepApprovalPanel panel;
  MapView map;
  Console() {
    QObject::connect(&session, &WalkSession::changed, &panel, [this] {
      panel.setPhase(QString::fromStdString(phaseName(session.executive().phase())));
      panel.showProposal(session.pending());
      map.setMap(session.executive().map());
      map.setProposal(session.pending());
    });
    QObject::connect(&map, &MapView::footholdClicked, &session,
                     [this](quint64 id, double x, double y) { session.editFoothold(id, x, y); });
    QObject::connect(&panel, &StepApprovalPanel::approveRequested, &session,
                     [this](quint64 id) { session.approve(id); });
    QObject::connect(&panel, &StepApprovalPanel::rejectRequested, &session,
                     [this](quint64 id) { session.reject(id, "rejected in the test"); });
    QObject::connect(&panel, &StepApprovalPanel::autoApproveChanged, &session,
                     &WalkSession::setAutoApprove);
    panel.show();
    map.resize(640, 640);
    map.show();
  }
  void click(const Eigen::Vector2d& world) {
    QTest::mouseClick(&map, Qt::LeftButton, {}, map.widgetPointOf(world).toPoint());
  }
  int movesSent() const {
    int n = 0;
    for (const auto& t : session.executive().tasks().tasks())
      n += (t.name == "LegMove" || t.name == "BodyMove") && t.started_s > 0;
    return n;
  }
};

}  // namespace

class StepApprovalTest : public QObject {
  Q_OBJECT

 private slots:
  void approvingAStepMovesTheRover() {
    Console c;
    QVERIFY(!c.panel.approveButton()->isEnabled());  // nothing to approve yet
    c.session.start(1);
    QTRY_VERIFY_WITH_TIMEOUT(c.panel.approveButton()->isEnabled(), 30000);
    QCOMPARE(c.panel.interlockTable()->rowCount(), 5);
    for (int row = 0; row < 5; ++row)
      QCOMPARE(c.panel.interlockTable()->item(row, 1)->text(), QString("passed"));
    const auto before = c.session.executive().reported()->body.xy;
    QTest::mouseClick(c.panel.approveButton(), Qt::LeftButton);
    QTRY_COMPARE_WITH_TIMEOUT(c.session.executive().phase(), Phase::kDone, 30000);
    const auto after = c.session.executive().reported()->body.xy;
    QVERIFY2((after - before).norm() > 0.1, "the rover did not move");
    QVERIFY(!c.panel.approveButton()->isEnabled());
    QVERIFY(c.session.linkAgeS().has_value());
    // A second walk from where the first ended.
    c.session.start(1);
    QTRY_VERIFY_WITH_TIMEOUT(c.panel.approveButton()->isEnabled(), 30000);
    QVERIFY((c.session.pending()->from.body.xy - after).norm() < 0.05);
  }

  void theMapShowsTheKnownCellsOfTheFirstScan() {
    Console c;
    c.session.start(1);
    QTRY_VERIFY_WITH_TIMEOUT(c.session.pending().has_value(), 30000);
    const QImage shot = c.map.grab().toImage();
    const QRect r = c.map.mapRect().toRect();
    int known = 0, unknown = 0;
    for (int y = r.top() + 1; y < r.bottom(); y += 2)
      for (int x = r.left() + 1; x < r.right(); x += 2) {
        const QColor p = shot.pixelColor(x, y);
        if (p == QColor(40, 40, 40))
          ++unknown;
        else
          ++known;
      }
    // The scanner sees ahead of the rover: the view holds both.
    QVERIFY2(known > 2000, qPrintable(QString::number(known)));
    QVERIFY(unknown > 2000);
    QVERIFY(c.session.executive().map().knownCount() > 1000);
  }

  void editingTheFootholdOnTheMapRechecksTheInterlocks() {
    Console c;
    c.session.start(6);
    // The first steps may move the body only: approve until a leg moves.
    for (int i = 0; i < 6; ++i) {
      QTRY_VERIFY_WITH_TIMEOUT(c.panel.approveButton()->isEnabled(), 30000);
      if (c.session.pending()->plan.leg >= 0) break;
      QTest::mouseClick(c.panel.approveButton(), Qt::LeftButton);
      QTRY_VERIFY_WITH_TIMEOUT(!c.session.pending().has_value(), 30000);
    }
    QVERIFY(c.session.pending()->plan.leg >= 0);
    const Eigen::Vector2d planned = c.session.pending()->plan.foothold.head<2>();
    // Four metres further ahead: out of the leg's reach.
    c.click(planned + Eigen::Vector2d(0, 4));
    QTRY_VERIFY(!c.panel.approveButton()->isEnabled());
    bool failed = false;
    for (int row = 0; row < c.panel.interlockTable()->rowCount(); ++row)
      failed |= c.panel.interlockTable()->item(row, 1)->text() == "FAILED";
    QVERIFY(failed);
    // Back where the planner put it: every interlock passes again.
    c.click(planned);
    QTRY_VERIFY(c.panel.approveButton()->isEnabled());
    QVERIFY((c.session.pending()->plan.foothold.head<2>() - planned).norm() < 0.1);
  }

  void rejectingAStepSendsNothing() {
    Console c;
    c.session.start(1);
    QTRY_VERIFY_WITH_TIMEOUT(c.panel.rejectButton()->isEnabled(), 30000);
    // (Xvfb has no window manager to activate the window for the shortcut.)
    QCOMPARE(c.panel.rejectButton()->shortcut(), QKeySequence(Qt::CTRL | Qt::Key_Backspace));
    QTest::mouseClick(c.panel.rejectButton(), Qt::LeftButton);
    QTRY_COMPARE_WITH_TIMEOUT(c.session.executive().phase(), Phase::kSuspended, 5000);
    QTest::qWait(300);
    QCOMPARE(c.movesSent(), 0);
    QVERIFY(!c.panel.rejectButton()->isEnabled());
  }

  void autoApproveIsVisibleAndWalksOnItsOwn() {
    Console c;
    c.session.start(2);
    c.panel.autoApproveSwitch()->setChecked(true);
    // The banner is red while auto-approve is on.
    const QImage shot = c.panel.banner()->grab().toImage();
    const QColor banner = shot.pixelColor(2, 2);
    QVERIFY2(banner.red() > 150 && banner.green() < 80, qPrintable(banner.name()));
    QTRY_COMPARE_WITH_TIMEOUT(c.session.executive().phase(), Phase::kDone, 60000);
    QCOMPARE(c.session.executive().stepsDone(), 2);
  }
};

QTEST_MAIN(StepApprovalTest)
#include "StepApprovalTest.moc"
