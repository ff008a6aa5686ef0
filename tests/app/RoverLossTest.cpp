// The rover's process killed mid-walk under a console connected over DDS:
// the console keeps running, its status bar says the link is
// lost, the walk is suspended with no step waiting for approval, the outage
// is in the table and the log, and the window is saved as a screenshot to
// look at; the rover restarted, Resume plans afresh from a new scan.
// Needs a display (xvfb-run).
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>
#include <QApplication>
#include <QCheckBox>
#include <QDir>
#include <QLabel>
#include <QPushButton>
#include <QStandardPaths>
#include <QTemporaryDir>
#include <QtTest/QtTest>
#include <fstream>

#include "app/gs/GroundStation.h"
#include "core/Resources.h"
#include "gait/RoverConfig.h"
#include "link/Signing.h"
#include "missionlog/MissionLog.h"
#include "sim/ScannerSim.h"
#include "tests/app/TestStation.h"
#include "widgets/CommandLogView.h"
#include "widgets/StepApprovalPanel.h"

using ambler::executive::Phase;

namespace {

// ambler-sim on `domain`, taking commands from the keys in `keys`, its
// moves taking `time_scale` times their modelled time.
pid_t startSimulator(int domain, const std::string& keys, const char* time_scale = "0") {
  const pid_t sim = ::fork();
  if (sim == 0) {
    const std::string d = std::to_string(domain);
    ::execl(AMBLER_SIM, AMBLER_SIM, "--domain", d.c_str(), "--keys", keys.c_str(), "--heartbeat-ms",
            "200", "--time-scale", time_scale, "--duration", "120", static_cast<char*>(nullptr));
    ::_exit(127);
  }
  return sim;
}

// The index of the first row at or after `from` whose text in column 2
// starts with one of `starts`, or -1.
int firstRow(const ambler::widgets::CommandLogView& table, int from, const QStringList& starts) {
  for (int row = from; row < table.rowCount(); ++row)
    for (const auto& start : starts)
      if (table.cellText(row, 2).startsWith(start)) return row;
  return -1;
}

using ambler::gs::test::options;

// Each operator's key file in `folder` (<operator>.key) and the rover's
// operators.json naming them all; returns the latter's path.
std::string writeKeys(const std::string& folder,
                      const std::vector<ambler::link::OperatorKey>& keys) {
  std::ofstream operators(folder + "/operators.json");
  operators << "{\"operators\": [";
  for (std::size_t i = 0; i < keys.size(); ++i) {
    ambler::link::writeOperatorKey(folder + "/" + keys[i].operator_id + ".key", keys[i]);
    operators << (i ? ", " : "") << "{\"operator\": \"" << keys[i].operator_id
              << "\", \"key_hex\": \"" << ambler::link::keyHex(keys[i]) << "\"}";
  }
  operators << "]}";
  return folder + "/operators.json";
}

// The station shown, connected over DDS with alice's key in `dir`,
// auto-approving; empty, or why it could not connect.
std::string connectAsAlice(ambler::gs::GroundStation& station, int domain,
                           const QTemporaryDir& dir) {
  station.window().show();
  ambler::widgets::ConnectChoice choice;
  choice.source = ambler::widgets::ConnectChoice::Source::kDds;
  choice.domain = domain;
  choice.key_file = dir.filePath("alice.key");
  const auto refusal = station.connectTo(choice);
  // As the operator does: the panel's switch, so that its banner says so.
  if (!refusal.refused()) station.window().approvalPanel()->autoApproveSwitch()->setChecked(true);
  return refusal.why();
}

}  // namespace

class RoverLossTest : public QObject {
  Q_OBJECT

 private slots:
  void initTestCase() { QStandardPaths::setTestModeEnabled(true); }

  void theConsoleSurvivesTheRoverGoingAway() {
    QTemporaryDir dir;
    const std::string folder = dir.path().toStdString();
    const ambler::link::OperatorKey alice{"alice", std::vector<std::uint8_t>(32, 7)};
    const std::string keys = writeKeys(folder, {alice});
    const int domain = 20 + int(::getpid() % 200);
    pid_t sim = startSimulator(domain, keys);

    ambler::gs::GroundStation station(options(dir.path()));
    station.window().resize(1400, 900);
    QCOMPARE(connectAsAlice(station, domain, dir), std::string());
    station.startWalk(20);
    // The session's latest state, each time asked (a new one replaces it).
    const auto walk = [&]() -> const ambler::gs::WalkState& { return station.session()->state(); };
    QTRY_VERIFY_WITH_TIMEOUT(walk().steps_done >= 1, 60000);

    ::kill(sim, SIGKILL);
    ::waitpid(sim, nullptr, 0);
    // DDS notices the vanished rover when its lease (10 s) runs out.
    QTRY_VERIFY_WITH_TIMEOUT(walk().link_lost.has_value(), 30000);
    QTRY_COMPARE_WITH_TIMEOUT(walk().phase, Phase::kSuspended, 5000);
    QVERIFY(!station.session()->pending());
    bool said = false;
    QTRY_VERIFY_WITH_TIMEOUT(
        [&] {
          for (const auto* label : station.window().findChildren<QLabel*>())
            said = said || label->text().contains("LINK LOST");
          return said;
        }(),
        5000);
    for (const auto* button : station.window().findChildren<QPushButton*>())
      if (button->text() == tr("&Approve")) QVERIFY(!button->isEnabled());
    auto& panel = *station.window().approvalPanel();
    QVERIFY(!panel.resumeButton()->isEnabled());
    QVERIFY(station.window().holdAction()->isEnabled());
    QVERIFY2(panel.reasonLabel()->text().contains("LINK LOST"),
             qPrintable(panel.reasonLabel()->text()));
    // The outage is an event in the table and in the mission log.
    auto& table = *station.window().commandLog();
    const int lost_row = firstRow(table, 0, {"link lost"});
    QVERIFY(lost_row >= 0);
    QCOMPARE(table.cellText(lost_row, 1), QString("ground"));
    {
      const ambler::missionlog::MissionLogReader log(station.session()->logPath());
      const auto products = log.products();
      QVERIFY(std::any_of(products.begin(), products.end(), [](const auto& p) {
        return p.kind == "event" && p.parameters.find("link lost") != std::string::npos;
      }));
    }
    QTest::qWait(500);  // the window keeps repainting meanwhile
    const QDir shots(AMBLER_SCREENSHOT_DIR);
    QVERIFY(shots.mkpath("."));
    QVERIFY(station.window().grab().save(shots.filePath("rover-lost.png")));

    // The rover comes back: once heard, Resume scans and plans afresh, so
    // the first move after the outage follows a scan taken after it.
    sim = startSimulator(domain, keys);
    QTRY_VERIFY_WITH_TIMEOUT(!walk().link_lost.has_value(), 30000);
    const int back_row = firstRow(table, lost_row, {"link back"});
    QVERIFY(back_row > lost_row);
    QTRY_VERIFY(panel.resumeButton()->isEnabled());
    QTest::mouseClick(panel.resumeButton(), Qt::LeftButton);
    QTRY_VERIFY_WITH_TIMEOUT(firstRow(table, back_row, {"LegMove", "BodyMove"}) > 0, 60000);
    const int scan_row = firstRow(table, back_row, {"AcquireScan"});
    QVERIFY(scan_row > back_row);
    QVERIFY(scan_row < firstRow(table, back_row, {"LegMove", "BodyMove"}));
    ::kill(sim, SIGTERM);
    ::waitpid(sim, nullptr, 0);
  }

  // A rover whose moves take the Ambler's own time: the status bar shows
  // the move under way, and HOLD suspends the walk while it runs.
  void aMoveUnderWayShowsInTheStatusBar() {
    QTemporaryDir dir;
    const std::string folder = dir.path().toStdString();
    const ambler::link::OperatorKey alice{"alice", std::vector<std::uint8_t>(32, 7)};
    const std::string keys = writeKeys(folder, {alice});
    const int domain = 20 + int((::getpid() + 53) % 200);
    const pid_t sim = startSimulator(domain, keys, "1");

    ambler::gs::GroundStation station(options(dir.path()));
    station.window().resize(1400, 900);
    QCOMPARE(connectAsAlice(station, domain, dir), std::string());
    station.startWalk(1);
    const auto walk = [&]() -> const ambler::gs::WalkState& { return station.session()->state(); };
    QTRY_VERIFY_WITH_TIMEOUT(walk().move_under_way.has_value(), 60000);
    const std::string type = walk().move_under_way->type;
    // The status bar's part on the move, once it shows one.
    const auto underWay = [&] {
      QString text;
      for (const auto* label : station.window().findChildren<QLabel*>())
        if (label->text().contains(" under way ")) text = label->text();
      return text;
    };
    QString shown;
    QTRY_VERIFY_WITH_TIMEOUT(!(shown = underWay()).isEmpty(), 5000);
    QVERIFY2(shown.contains(QString::fromStdString(type) + " under way"), qPrintable(shown));
    QVERIFY2(shown.contains("held after"), qPrintable(shown));
    const QDir shots(AMBLER_SCREENSHOT_DIR);
    QVERIFY(shots.mkpath("."));
    QVERIFY(station.window().grab().save(shots.filePath("move-under-way.png")));
    // HOLD stops the next motion, not this one: the move stays in view, and
    // Resume waits for its end before the scan, which the rover would refuse
    // until then.
    const std::uint64_t sequence = walk().move_under_way->sequence;
    station.window().holdAction()->trigger();
    QTRY_COMPARE_WITH_TIMEOUT(walk().phase, Phase::kSuspended, 5000);
    QVERIFY(walk().move_under_way.has_value());
    QCOMPARE(walk().move_under_way->sequence, sequence);
    QTRY_VERIFY_WITH_TIMEOUT(!(shown = underWay()).contains("held after"), 5000);
    QVERIFY2(shown.contains(QString::fromStdString(type) + " under way"), qPrintable(shown));
    auto& panel = *station.window().approvalPanel();
    QTRY_VERIFY(panel.resumeButton()->isEnabled());
    const auto& table = *station.window().commandLog();
    const int resumed_row = table.rowCount();
    QTest::mouseClick(panel.resumeButton(), Qt::LeftButton);
    QTRY_COMPARE_WITH_TIMEOUT(walk().phase, Phase::kAwaitingMoveEnd, 5000);
    QTest::qWait(300);  // the panel and status bar follow
    QVERIFY(station.window().grab().save(shots.filePath("resumed-during-move.png")));
    QTRY_COMPARE_WITH_TIMEOUT(walk().phase, Phase::kExecuting, 90000);
    for (int row = resumed_row; row < table.rowCount(); ++row)
      QVERIFY2(table.cellText(row, 3) != "refused",
               qPrintable(table.cellText(row, 2) + ": " + table.cellText(row, 4)));
    ::kill(sim, SIGTERM);
    ::waitpid(sim, nullptr, 0);
  }

  // Two consoles on one rover: the GUI walks, another console
  // (ambler-cli drive --take-over) asks, the operator hands over from the
  // Rover menu, the other console walks a step, and the GUI asks back.
  void theOperatorHandsCommandAuthorityOverAndAsksForItBack() {
    QTemporaryDir dir;
    const std::string folder = dir.path().toStdString();
    const ambler::link::OperatorKey alice{"alice", std::vector<std::uint8_t>(32, 7)},
        bob{"bob", std::vector<std::uint8_t>(32, 8)};
    const std::string keys = writeKeys(folder, {alice, bob});
    const int domain = 20 + int((::getpid() + 97) % 200);
    const pid_t sim = startSimulator(domain, keys);

    ambler::gs::GroundStation station(options(dir.path()));
    QCOMPARE(connectAsAlice(station, domain, dir), std::string());
    station.startWalk(1);
    const auto walk = [&]() -> const ambler::gs::WalkState& { return station.session()->state(); };
    QTRY_COMPARE_WITH_TIMEOUT(walk().phase, Phase::kDone, 60000);
    QTRY_COMPARE_WITH_TIMEOUT(walk().authority, walk().console, 5000);
    auto* hand_over = station.window().handOverAction();
    auto* ask = station.window().requestAuthorityAction();
    QTRY_VERIFY(!ask->isEnabled());
    QVERIFY(!hand_over->isEnabled());  // nobody asks

    const pid_t other = ::fork();
    if (other == 0) {
      const std::string d = std::to_string(domain), key = folder + "/bob.key",
                        log = folder + "/bob.sqlite", out = folder + "/bob.out";
      std::freopen(out.c_str(), "w", stdout);
      ::execl(AMBLER_CLI, AMBLER_CLI, "drive", "--domain", d.c_str(), "--key", key.c_str(), "--log",
              log.c_str(), "--steps", "1", "--auto-approve", "--take-over", "--timeout", "60",
              static_cast<char*>(nullptr));
      ::_exit(127);
    }
    QTest::qWait(1500);  // discovery
    ::kill(other, SIGUSR1);
    QTRY_VERIFY_WITH_TIMEOUT(hand_over->isEnabled(), 10000);
    QVERIFY2(hand_over->text().contains("bob@"), qPrintable(hand_over->text()));
    hand_over->trigger();
    QTRY_VERIFY_WITH_TIMEOUT(walk().authority.rfind("bob@", 0) == 0, 10000);
    QTRY_VERIFY(ask->isEnabled());
    const auto bob_said = [&] {
      std::ifstream in(folder + "/bob.out");
      return std::string(std::istreambuf_iterator<char>(in), {});
    };
    // Bob walked his step (his summary line says so).
    QTRY_VERIFY2_WITH_TIMEOUT(bob_said().find("\"stopped\":\"done\"") != std::string::npos,
                              bob_said().substr(0, 800).c_str(), 60000);
    ::waitpid(other, nullptr, 0);
    const QDir shots(AMBLER_SCREENSHOT_DIR);
    QVERIFY(shots.mkpath("."));
    QVERIFY(station.window().grab().save(shots.filePath("authority-handed-over.png")));

    // Bob's console has gone: the rover holds once his heartbeats stop,
    // and authority lapses with his link; the operator asks and has it.
    QTRY_VERIFY_WITH_TIMEOUT(walk().rover_holding.rfind("link lost", 0) == 0, 10000);
    QTRY_VERIFY_WITH_TIMEOUT(walk().authority.empty(), 5000);
    ask->trigger();
    QTRY_COMPARE_WITH_TIMEOUT(walk().authority, walk().console, 5000);
    QTRY_VERIFY(!ask->isEnabled());
    ::kill(sim, SIGTERM);
    ::waitpid(sim, nullptr, 0);
  }
};

QTEST_MAIN(RoverLossTest)
#include "RoverLossTest.moc"
