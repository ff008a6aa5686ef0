#include "mapping/ScanChain.h"

#include <stdexcept>

namespace ambler::mapping {

bool ScanChain::applies(const Registration& r) {
  return r.quality.verdict == Verdict::kTrusted || r.quality.verdict == Verdict::kDoubtful;
}

void ScanChain::add(Cloud scan, const Eigen::Vector3d& scanner) {
  waiting_.push_back({std::move(scan), scanner});
}

std::optional<ScanChain::Job> ScanChain::next() {
  if (in_flight_ || waiting_.empty()) return std::nullopt;
  Scan scan = std::move(waiting_.front());
  waiting_.pop_front();
  if (registered_.empty()) {
    registered_.push_back(std::move(scan.points));
    last_scanner_ = scan.scanner;
    last_ = {};
    return next();
  }
  in_flight_ = std::move(scan);
  return Job{in_flight_->points, registered_.back(), {in_flight_->scanner, last_scanner_}};
}

void ScanChain::finish(const Registration& registration) {
  if (!in_flight_) return;  // cleared while it ran
  last_ = registration;
  if (applies(registration)) {
    for (auto& p : in_flight_->points) p = registration.transform * p;
    in_flight_->scanner = registration.transform * in_flight_->scanner;
  }
  registered_.push_back(std::move(in_flight_->points));
  last_scanner_ = in_flight_->scanner;
  in_flight_.reset();
}

void ScanChain::clear() {
  waiting_.clear();
  in_flight_.reset();
  registered_.clear();
  last_ = {};
}

Cloud ScanChain::merged() const {
  Cloud all;
  for (const auto& scan : registered_) all.insert(all.end(), scan.begin(), scan.end());
  return all;
}

Registration ScanChain::run(const Job& job, const RegistrationOptions& options) {
  try {
    return registerClouds(job.source, job.target, Eigen::Isometry3d::Identity(), options,
                          job.scanners);
  } catch (const std::invalid_argument&) {
    return {};
  }
}

}  // namespace ambler::mapping
