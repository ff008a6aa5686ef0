#include "app/gs/WalkSession.h"

#include <chrono>
#include <random>

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

WalkSession::WalkSession(const walk::WalkConfig& config, std::uint64_t seed,
                         const QString& operator_id, QObject* parent)
    : QObject(parent), context_(config.gait), operator_id_(operator_id) {
  const auto key = sessionKey(operator_id);
  rover::SimulatedRoverOptions options;
  options.seed = seed;
  options.operators = {key};
  rover_ = std::make_unique<rover::InProcessLink>(config, options);
  link_ = std::make_unique<link::WatchedLink>(*rover_, health_, [this] { return nowS(); });
  signer_ = std::make_unique<link::CommandSigner>(key);
  executive_ = std::make_unique<executive::WalkExecutive>(*link_, *signer_, gate_, context_);
  connect(&timer_, &QTimer::timeout, this, &WalkSession::poll);
}

WalkSession::~WalkSession() = default;

double WalkSession::nowS() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

void WalkSession::start(int steps) {
  executive::ExecutiveOptions options;
  options.steps = steps;
  executive_ =
      std::make_unique<executive::WalkExecutive>(*link_, *signer_, gate_, context_, options);
  executive_->start(nowS(), true);
  timer_.start(50);
  emit changed();
}

void WalkSession::poll() {
  executive_->poll(nowS(), std::chrono::milliseconds(0));
  const auto pending = gate_.pending() ? std::optional<quint64>(gate_.pending()->id) : std::nullopt;
  if (pending != last_pending_ || executive_->phase() != last_phase_) {
    last_pending_ = pending;
    last_phase_ = executive_->phase();
    emit changed();
  }
}

QString WalkSession::approve(quint64 proposal) {
  const auto why = gate_.approve(proposal, operator_id_.toStdString(), nowS());
  poll();
  return QString::fromStdString(why);
}

QString WalkSession::reject(quint64 proposal, const QString& reason) {
  const auto why = gate_.reject(proposal, operator_id_.toStdString(), nowS(), reason.toStdString());
  poll();
  return QString::fromStdString(why);
}

QString WalkSession::editFoothold(quint64 proposal, double x_m, double y_m) {
  const auto why =
      executive_->editFoothold(proposal, {x_m, y_m}, operator_id_.toStdString(), nowS());
  emit changed();
  return QString::fromStdString(why);
}

void WalkSession::setAutoApprove(bool on) {
  gate_.setMode(on ? executive::ApprovalMode::kAutoApprove : executive::ApprovalMode::kOperator);
  // A step already waiting is released now if it passes its interlocks.
  if (on && gate_.pending() && gate_.pending()->interlocks.passed())
    gate_.approve(gate_.pending()->id, executive::kAutoApprover, nowS());
  emit changed();
}

QString WalkSession::linkDescription() const { return QString::fromStdString(link_->describe()); }

std::optional<double> WalkSession::linkAgeS() const { return health_.ageS(nowS()); }

}  // namespace ambler::gs
