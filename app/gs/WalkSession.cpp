#include "app/gs/WalkSession.h"

#include <chrono>
#include <random>

#include "link/Limits.h"
#include "rover/InProcessLink.h"

namespace ambler::gs {

namespace {

link::OperatorKey sessionKey(const QString& operator_id) {
  std::random_device random;
  std::vector<std::uint8_t> key(32);
  for (auto& b : key) b = std::uint8_t(random());
  return {operator_id.toStdString(), key};
}

}  // namespace

RoverConnection simulatorConnection(const rover::SimulatedRoverConfig& config, std::uint64_t seed,
                                    const QString& operator_id) {
  RoverConnection c;
  c.key = sessionKey(operator_id);
  rover::SimulatedRoverOptions options;
  options.course.seed = seed;
  options.operators = {c.key};
  c.link = std::make_unique<rover::InProcessLink>(config, options);
  c.mission = "ambler-gs walk on course " + std::to_string(seed);
  return c;
}

WalkSession::WalkSession(const gait::GaitContext& context, RoverConnection rover,
                         const std::filesystem::path& log_path, QObject* parent)
    : QObject(parent),
      context_(context),
      log_path_(log_path),
      log_(log_path, rover.mission),
      gate_([this](const missionlog::Decision& d) {
        log_.record(d);
        table_.decided(d);
      }),
      operator_id_(QString::fromStdString(rover.key.operator_id)) {
  rover_ = std::move(rover);
  recording_ = std::make_unique<missionlog::RecordingLink>(*rover_.link, log_);
  link_ = std::make_unique<link::WatchedLink>(
      *recording_, health_, [this] { return nowS(); },
      link::LinkObserver{[this](const link::Command& c) { table_.sent(nowS(), c); },
                         [this](const link::Telemetry& t) { table_.received(nowS(), t); }});
  signer_ = std::make_unique<link::CommandSigner>(rover_.key, rover_.first_sequence);
  makeExecutive({});
  connect(&timer_, &QTimer::timeout, this, &WalkSession::poll);
}

WalkSession::~WalkSession() = default;

double WalkSession::nowS() const { return missionlog::groundClockS(); }

void WalkSession::makeExecutive(const executive::ExecutiveOptions& options) {
  executive_ =
      std::make_unique<executive::WalkExecutive>(*link_, *signer_, gate_, context_, options);
  executive_->onProduct([this](double t, const std::string& kind, const std::string& parameters) {
    log_.recordProduct(t, kind, parameters);
  });
  executive_->onScanMapped([this](const sensor::RangeImage& scan) { emit scanMapped(scan); });
  executive_->onEvent([this](const executive::ExecutiveEvent& e) {
    log_.recordEvent(e.time_s, e.what);
    table_.noted(e.time_s, e.what);
    emit eventNoted(QString::fromStdString(e.what));
  });
}

void WalkSession::start(int steps) {
  executive::ExecutiveOptions options;
  options.steps = steps;
  options.rover_id = rover_.rover_id;
  makeExecutive(options);
  executive_->start(nowS(), true);
  timer_.start(50);
  emit changed();
}

void WalkSession::poll() {
  executive_->poll(nowS(), std::chrono::milliseconds(0));
  const auto pending = gate_.pending() ? std::optional<quint64>(gate_.pending()->id) : std::nullopt;
  if (pending != last_pending_ || executive_->phase() != last_phase_ ||
      table_.rows().size() != last_rows_) {
    last_pending_ = pending;
    last_phase_ = executive_->phase();
    last_rows_ = table_.rows().size();
    emit changed();
  }
  answerGrasp();  // an answer fills its row in place
}

void WalkSession::answerGrasp() {
  if (!grasp_row_ || *grasp_row_ >= table_.rows().size()) return;
  const auto& row = table_.rows()[*grasp_row_];
  if (row.outcome != "accepted" && row.outcome != "refused") return;
  grasp_row_.reset();
  emit graspAnswered(row.outcome == "accepted", QString::fromStdString(row.reason));
  emit changed();  // the table shows the answer
}

Refusal WalkSession::approve(quint64 proposal) {
  auto done = gate_.approve(proposal, operator_id_.toStdString(), nowS());
  poll();
  return done;
}

Refusal WalkSession::reject(quint64 proposal, const QString& reason) {
  auto done = gate_.reject(proposal, operator_id_.toStdString(), nowS(), reason.toStdString());
  poll();
  return done;
}

Refusal WalkSession::editFoothold(quint64 proposal, double x_m, double y_m) {
  auto done = executive_->editFoothold(proposal, {x_m, y_m}, operator_id_.toStdString(), nowS());
  emit changed();
  return done;
}

void WalkSession::hold() {
  executive_->hold(nowS(), operator_id_.toStdString());
  if (!timer_.isActive()) timer_.start(50);  // for the rover's answer
  emit changed();
}

void WalkSession::resume() {
  executive_->resume(nowS());
  if (!timer_.isActive()) timer_.start(50);
  emit changed();
}

void WalkSession::setAutoApprove(bool on) {
  gate_.setMode(on ? executive::ApprovalMode::kAutoApprove : executive::ApprovalMode::kOperator);
  // A step already waiting is released now if it passes its interlocks.
  if (on && gate_.pending() && gate_.pending()->interlocks.passed())
    if (const auto refused = gate_.approve(gate_.pending()->id, executive::kAutoApprover, nowS());
        refused.refused())
      emit eventNoted(tr("auto-approve refused the waiting step: %1")
                          .arg(QString::fromStdString(refused.why())));
  emit changed();
}

Refusal WalkSession::sendGrasp(const sampling::GraspPlan& plan, const std::string& detail) {
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
  const missionlog::Decision decision{nowS(), operator_id_.toStdString(), 0,
                                      missionlog::Verdict::kApproved,
                                      "{\"grasp\": " + detail + "}"};
  log_.record(decision);
  table_.decided(decision);
  link::Command command;
  command.rover_id = rover_.rover_id;
  command.time_s = nowS();
  command.body = grasp;
  signer_->sign(command);
  grasp_row_ = table_.rows().size();  // the row the send is about to add
  try {
    link_->send(command);
  } catch (const link::LinkError& e) {
    grasp_row_.reset();
    return Refusal::because(std::string("grasp approved but not sent: ") + e.what());
  }
  if (!timer_.isActive()) timer_.start(50);  // for the answer
  emit changed();
  return {};
}

QString WalkSession::linkDescription() const { return QString::fromStdString(link_->describe()); }

std::optional<double> WalkSession::linkAgeS() const { return health_.ageS(nowS()); }

}  // namespace ambler::gs
