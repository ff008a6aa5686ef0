#include "app/gs/WalkSession.h"

#include <QTimer>
#include <chrono>
#include <random>

#include "link/Limits.h"
#include "link/Signing.h"
#include "missionlog/ReplayLinks.h"
#include "rover/InProcessLink.h"

namespace ambler::gs {

namespace {

link::OperatorKey sessionKey(const QString& operator_id) {
  std::random_device random;
  std::vector<std::uint8_t> key(32);
  for (auto& b : key) b = std::uint8_t(random());
  return {operator_id.toStdString(), key};
}

// Between changes the rover still moves: its reports reach the views this
// often.
constexpr double kTelemetryPeriodS = 0.25;

}  // namespace

RoverConnection simulatorConnection(const rover::SimulatedRoverConfig& config, std::uint64_t seed,
                                    const QString& operator_id,
                                    const rover::SimulatedGround& ground) {
  RoverConnection c;
  c.key = sessionKey(operator_id);
  rover::SimulatedRoverOptions options;
  options.operators = {c.key};
  // The ground is drawn where the link opens, on the session's thread.
  c.open = [config, options, ground, seed] {
    rover::SimulatedRoverOptions on_ground = options;
    ground.applyTo(seed, on_ground);
    return std::make_unique<rover::InProcessLink>(config, on_ground);
  };
  const std::string where = ground.name(seed);
  c.description = "built-in simulator on " + where;
  c.mission = "ambler-gs walk on " + where;
  return c;
}

// The session's work on its own thread: the link, the log, the gate and
// the executive, polled by a timer of this thread. Made on the GUI thread,
// then only touched from its own; it tells the session by queued calls.
class WalkWorker : public QObject {
 public:
  WalkWorker(WalkSession& session, const gait::GaitContext& context, RoverConnection rover,
             const std::filesystem::path& log_path)
      : session_(session),
        context_(context),
        log_path_(log_path),
        rover_(std::move(rover)),
        gate_([this](const missionlog::Decision& d) {
          log_->record(d);
          table_.decided(d);
          rows_changed_ = true;
        }) {
    signer_ = std::make_unique<link::CommandSigner>(rover_.key, rover_.first_sequence);
    timer_.setParent(this);  // moves to the session's thread with it
    connect(&timer_, &QTimer::timeout, this, [this] { poll(); });
  }

  // The first call on the session's thread (the log's file is created and
  // synced here, not on the GUI thread); a log or a link that cannot be
  // opened is refused, and the session then does nothing.
  void open() {
    try {
      log_ = std::make_unique<missionlog::MissionLog>(log_path_, rover_.mission);
    } catch (const std::exception& e) {
      return tellRefusal(OperatorAction::kConnect,
                         Refusal::because(std::string("No session without its log: ") + e.what()));
    }
    try {
      rover_link_ = rover_.open();
    } catch (const std::exception& e) {
      return tellRefusal(OperatorAction::kConnect,
                         Refusal::because(std::string("Could not connect: ") + e.what()));
    }
    recording_ = std::make_unique<missionlog::RecordingLink>(*rover_link_, *log_);
    link_ = std::make_unique<link::WatchedLink>(
        *recording_, health_, link::utcNowS,
        link::LinkObserver{[this](const link::Command& c) {
                             table_.sent(link::utcNowS(), c);
                             rows_changed_ = true;
                           },
                           [this](const link::Telemetry& t) {
                             table_.received(link::utcNowS(), t);
                             rows_changed_ = heard_ = true;
                           }});
    makeExecutive({});
  }

  bool opened() const { return executive_ != nullptr; }

  void start(int steps, const gait::Heading& heading) {
    executive::ExecutiveOptions options;
    options.steps = steps;
    options.heading = heading;
    options.rover_id = rover_.rover_id;
    makeExecutive(options);
    executive_->start(link::utcNowS(), true);
    keepPolling();
    publish(true);
  }

  void approve(quint64 proposal, const std::string& who) {
    tellRefusal(OperatorAction::kApprove, gate_.approve(proposal, who, link::utcNowS()));
    poll();
  }

  void reject(quint64 proposal, const std::string& who, const std::string& reason) {
    tellRefusal(OperatorAction::kReject, gate_.reject(proposal, who, link::utcNowS(), reason));
    poll();
  }

  void editFoothold(quint64 proposal, const Eigen::Vector2d& xy, const std::string& who) {
    tellRefusal(OperatorAction::kEditFoothold,
                executive_->editFoothold(proposal, xy, who, link::utcNowS()));
    ++proposal_revision_;
    publish(true);
  }

  void hold(const std::string& who) {
    executive_->hold(link::utcNowS(), who);
    keepPolling();  // for the rover's answer
    publish(true);
  }

  void resume() {
    executive_->resume(link::utcNowS());
    keepPolling();
    publish(true);
  }

  void setAutoApprove(bool on) {
    gate_.setMode(on ? executive::ApprovalMode::kAutoApprove : executive::ApprovalMode::kOperator);
    // A step already waiting is released now if it passes its interlocks.
    if (on && gate_.pending() && gate_.pending()->interlocks.passed()) {
      const auto done =
          gate_.approve(gate_.pending()->id, executive::kAutoApprover, link::utcNowS());
      tellRefusal(OperatorAction::kAutoApprove, done);
    }
    publish(true);
  }

  void requestAuthority() {
    tellRefusal(OperatorAction::kAuthority, sendSigned(link::RequestAuthority{}));
    keepPolling();  // for the rover's heartbeat that tells who holds it
    publish(true);
  }

  // Between two steps only: a step half carried out is the holder's to
  // finish.
  void handOver() {
    const auto phase = executive_->phase();
    Refusal refusal;
    if (table_.authority() != signer_->console())
      refusal = Refusal::because("this console does not hold command authority");
    else if (table_.authorityRequest().empty())
      refusal = Refusal::because("no console has asked for command authority");
    else if (phase == executive::Phase::kExecuting || phase == executive::Phase::kScanning ||
             phase == executive::Phase::kAwaitingMoveEnd)
      refusal = Refusal::because("the walk is " + executive::phaseName(phase) +
                                 ": hand over once the step has ended");
    else
      refusal = sendSigned(link::HandOver{table_.authorityRequest()});
    tellRefusal(OperatorAction::kAuthority, refusal);
    keepPolling();
    publish(true);
  }

  void sendGrasp(const sampling::GraspPlan& plan, const std::string& detail,
                 const std::string& who) {
    const auto sent = trySendGrasp(plan, detail, who);
    if (sent.refused()) return tellRefusal(OperatorAction::kGrasp, sent);
    tell([](WalkSession& s) { emit s.graspSent(); });
    keepPolling();  // for the answer
    publish(true);
  }

 private:
  void makeExecutive(const executive::ExecutiveOptions& options) {
    executive_ =
        std::make_unique<executive::WalkExecutive>(*link_, *signer_, gate_, context_, options);
    executive_->onProduct([this](double t, const std::string& kind, const std::string& parameters) {
      log_->recordProduct(t, kind, parameters);
    });
    executive_->onScanMapped([this](const sensor::RangeImage& scan) {
      map_changed_ = true;
      tell([scan](WalkSession& s) { emit s.scanMapped(scan); });
    });
    executive_->onEvent([this](const executive::ExecutiveEvent& e) {
      log_->recordEvent(e.time_s, e.what);
      table_.noted(e.time_s, e.what);
      rows_changed_ = true;
      tell([what = QString::fromStdString(e.what)](WalkSession& s) { emit s.eventNoted(what); });
    });
    map_changed_ = true;  // a new walk maps afresh
  }

  void keepPolling() {
    if (!timer_.isActive()) timer_.start(50);
  }

  void poll() {
    executive_->poll(link::utcNowS(), std::chrono::milliseconds(0));
    answerGrasp();
    publish(false);
  }

  // A new state when something the operator sees has changed, and the
  // rover's newest reports a few times a second.
  void publish(bool force) {
    const auto pending = gate_.pending() ? std::optional(gate_.pending()->id) : std::nullopt;
    if (pending != last_pending_) ++proposal_revision_;
    const bool changed = force || map_changed_ || rows_changed_ || pending != last_pending_ ||
                         executive_->phase() != last_phase_;
    const double now = link::utcNowS();
    if (!changed && !(heard_ && now - published_s_ >= kTelemetryPeriodS)) return;
    last_pending_ = pending;
    last_phase_ = executive_->phase();
    published_s_ = now;
    heard_ = false;
    if (std::exchange(map_changed_, false) || !map_)
      map_ = std::make_shared<const terrain::ElevationMap>(executive_->map());
    if (std::exchange(rows_changed_, false))
      rows_ = std::make_shared<const std::vector<replay::LogRow>>(table_.rows());
    auto state = std::make_shared<WalkState>();
    state->phase = executive_->phase();
    state->steps_done = executive_->stepsDone();
    state->suspended_because = executive_->suspendedBecause();
    state->rover_holding = executive_->roverHolding();
    state->link_lost = executive_->linkLost();
    state->pending = gate_.pending();
    state->proposal_revision = proposal_revision_;
    state->reported = executive_->reported();
    state->report = executive_->report();
    state->tasks = executive_->tasks().tasks();
    state->map = map_;
    state->rows = rows_;
    state->last_heard_s = health_.lastHeardS();
    state->round_trip_s = executive_->roundTripS();
    state->commands_in_flight = table_.awaiting();
    state->move_under_way = executive_->moveUnderWay();
    state->authority = table_.authority();
    state->authority_request = table_.authorityRequest();
    state->console = signer_->console();
    tell([state = std::shared_ptr<const WalkState>(std::move(state))](WalkSession& s) {
      s.take(state);
    });
  }

  void answerGrasp() {
    if (!grasp_row_ || *grasp_row_ >= table_.rows().size()) return;
    const auto& row = table_.rows()[*grasp_row_];
    if (row.outcome != "accepted" && row.outcome != "refused") return;
    grasp_row_.reset();
    tell([accepted = row.outcome == "accepted", reason = QString::fromStdString(row.reason)](
             WalkSession& s) { emit s.graspAnswered(accepted, reason); });
  }

  Refusal trySendGrasp(const sampling::GraspPlan& plan, const std::string& detail,
                       const std::string& who) {
    if (!plan.ok) return Refusal::because("no grasp to send: " + plan.reason);
    const auto phase = executive_->phase();
    if (phase != executive::Phase::kIdle && phase != executive::Phase::kDone &&
        phase != executive::Phase::kSuspended)
      return Refusal::because("the walk is " + executive::phaseName(phase) +
                              ": grasp once it has stopped");
    const link::Grasp grasp{plan.centre.x(), plan.centre.y(), plan.centre.z(), plan.yaw_rad,
                            plan.opening_m};
    if (auto outside = link::outsideLimits(grasp, context_.model, context_.gait); outside.refused())
      return outside;
    const missionlog::Decision decision{link::utcNowS(), who, 0, missionlog::Verdict::kApproved,
                                        "{\"grasp\": " + detail + "}"};
    log_->record(decision);
    table_.decided(decision);
    rows_changed_ = true;
    const link::Command command = signer_->command(rover_.rover_id, grasp);
    grasp_row_ = table_.rows().size();  // the row the send is about to add
    try {
      link_->send(command);
    } catch (const link::LinkError& e) {
      grasp_row_.reset();
      return Refusal::because(std::string("grasp approved but not sent: ") + e.what());
    }
    return {};
  }

  Refusal sendSigned(link::CommandBody body) {
    const link::Command command = signer_->command(rover_.rover_id, std::move(body));
    try {
      link_->send(command);
    } catch (const link::LinkError& e) {
      return Refusal::because(link::typeName(command.body) + " not sent: " + e.what());
    }
    return {};
  }

  void tellRefusal(OperatorAction action, const Refusal& refusal) {
    if (!refusal.refused()) return;
    tell([action, why = QString::fromStdString(refusal.why())](WalkSession& s) {
      emit s.refused(action, why);
    });
  }

  // Runs `f` on the GUI thread; dropped if the session is gone by then.
  template <typename F>
  void tell(F f) {
    QMetaObject::invokeMethod(
        &session_, [s = &session_, f = std::move(f)] { f(*s); }, Qt::QueuedConnection);
  }

  WalkSession& session_;
  gait::GaitContext context_;
  std::filesystem::path log_path_;
  std::unique_ptr<missionlog::MissionLog> log_;  // from open() on
  replay::CommandTable table_;
  RoverConnection rover_;
  std::unique_ptr<link::Link> rover_link_;
  std::unique_ptr<link::Link> recording_;  // rover_link_, to log_
  link::LinkHealth health_;
  std::unique_ptr<link::Link> link_;  // recording_, watched for health_ and table_
  std::unique_ptr<link::CommandSigner> signer_;
  executive::ApprovalGate gate_;
  std::unique_ptr<executive::WalkExecutive> executive_;
  QTimer timer_;
  std::optional<std::size_t> grasp_row_;  // the last grasp's row, until answered
  // What the last state told, and what has changed since.
  std::optional<quint64> last_pending_;
  executive::Phase last_phase_ = executive::Phase::kIdle;
  std::uint64_t proposal_revision_ = 0;
  double published_s_ = 0.0;
  bool map_changed_ = true, rows_changed_ = true, heard_ = false;
  std::shared_ptr<const terrain::ElevationMap> map_;
  std::shared_ptr<const std::vector<replay::LogRow>> rows_;
};

WalkSession::WalkSession(const gait::GaitContext& context, RoverConnection rover,
                         const std::filesystem::path& log_path, QObject* parent)
    : QObject(parent),
      log_path_(log_path),
      link_description_(rover.description),
      operator_id_(rover.key.operator_id) {
  auto worker = std::make_unique<WalkWorker>(*this, context, std::move(rover), log_path);
  thread_.setObjectName("walk session");
  worker->moveToThread(&thread_);
  worker_ = worker.release();
  thread_.start();
  QMetaObject::invokeMethod(worker_, [w = worker_] { w->open(); });
}

WalkSession::~WalkSession() {
  QMetaObject::invokeMethod(
      worker_, [w = worker_] { delete w; }, Qt::BlockingQueuedConnection);
  thread_.quit();
  thread_.wait();
}

void WalkSession::take(std::shared_ptr<const WalkState> state) {
  state_ = std::move(state);
  emit changed();
}

std::optional<double> WalkSession::linkAgeS() const {
  if (!state_->last_heard_s) return std::nullopt;
  return link::utcNowS() - *state_->last_heard_s;
}

// Carried out on the session's thread, in the order asked; nothing once
// the link could not be opened.
template <typename F>
void WalkSession::ask(F f) {
  QMetaObject::invokeMethod(worker_, [w = worker_, f = std::move(f)] {
    if (w->opened()) f(*w);
  });
}

void WalkSession::start(int steps, const gait::Heading& heading) {
  ask([steps, heading](WalkWorker& w) { w.start(steps, heading); });
}

void WalkSession::approve(quint64 proposal) {
  ask([proposal, who = operator_id_](WalkWorker& w) { w.approve(proposal, who); });
}

void WalkSession::reject(quint64 proposal, const QString& reason) {
  ask([proposal, who = operator_id_, why = reason.toStdString()](WalkWorker& w) {
    w.reject(proposal, who, why);
  });
}

void WalkSession::editFoothold(quint64 proposal, double x_m, double y_m) {
  ask([proposal, x_m, y_m, who = operator_id_](WalkWorker& w) {
    w.editFoothold(proposal, {x_m, y_m}, who);
  });
}

void WalkSession::setAutoApprove(bool on) {
  ask([on](WalkWorker& w) { w.setAutoApprove(on); });
}

void WalkSession::hold() {
  ask([who = operator_id_](WalkWorker& w) { w.hold(who); });
}

void WalkSession::resume() {
  ask([](WalkWorker& w) { w.resume(); });
}

void WalkSession::sendGrasp(const sampling::GraspPlan& plan, const std::string& detail) {
  ask([plan, detail, who = operator_id_](WalkWorker& w) { w.sendGrasp(plan, detail, who); });
}

void WalkSession::requestAuthority() {
  ask([](WalkWorker& w) { w.requestAuthority(); });
}

void WalkSession::handOver() {
  ask([](WalkWorker& w) { w.handOver(); });
}

}  // namespace ambler::gs
