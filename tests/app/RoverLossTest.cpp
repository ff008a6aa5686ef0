// The rover's process killed mid-walk under a console connected over DDS
// (issue 28): the console keeps running, its status bar says the link is
// lost, the walk is suspended with no step waiting for approval, and the
// window is saved as a screenshot to look at. Needs a display (xvfb-run).
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>
#include <QApplication>
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
#include "sim/ScannerSim.h"

using ambler::executive::Phase;

namespace {

ambler::gs::StationOptions options(const QString& log_dir) {
  ambler::gs::StationOptions o;
  o.operator_id = "alice";
  o.log_dir = log_dir;
  o.ground = ambler::gait::readInstalledGaitContext();
  o.simulator = ambler::rover::readInstalledSimulatedRoverConfig();
  o.scanner = ambler::sim::readScannerModel(ambler::findResource("config/scanner.json"));
  return o;
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
    ambler::link::writeOperatorKey(folder + "/alice.key", alice);
    std::ofstream(folder + "/operators.json")
        << "{\"operators\": [{\"operator\": \"alice\", \"key_hex\": \""
        << ambler::link::keyHex(alice) << "\"}]}";
    const int domain = 20 + int(::getpid() % 200);
    const pid_t sim = ::fork();
    if (sim == 0) {
      const std::string d = std::to_string(domain), keys = folder + "/operators.json";
      ::execl(AMBLER_SIM, AMBLER_SIM, "--domain", d.c_str(), "--keys", keys.c_str(),
              "--heartbeat-ms", "200", "--duration", "120", static_cast<char*>(nullptr));
      ::_exit(127);
    }

    ambler::gs::GroundStation station(options(dir.path()));
    station.window().resize(1400, 900);
    station.window().show();
    ambler::widgets::ConnectChoice choice;
    choice.source = ambler::widgets::ConnectChoice::Source::kDds;
    choice.domain = domain;
    choice.key_file = dir.filePath("alice.key");
    QCOMPARE(station.connectTo(choice), QString());
    station.session()->setAutoApprove(true);
    station.startWalk(20);
    const auto& executive = station.session()->executive();
    QTRY_VERIFY_WITH_TIMEOUT(executive.stepsDone() >= 1, 60000);

    ::kill(sim, SIGKILL);
    ::waitpid(sim, nullptr, 0);
    // DDS notices the vanished rover when its lease (10 s) runs out.
    QTRY_VERIFY_WITH_TIMEOUT(executive.linkLost().has_value(), 30000);
    QTRY_COMPARE_WITH_TIMEOUT(executive.phase(), Phase::kSuspended, 5000);
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
    QTest::qWait(500);  // the window keeps repainting meanwhile
    const QDir shots(AMBLER_SCREENSHOT_DIR);
    QVERIFY(shots.mkpath("."));
    QVERIFY(station.window().grab().save(shots.filePath("rover-lost.png")));
  }
};

QTEST_MAIN(RoverLossTest)
#include "RoverLossTest.moc"
