#pragma once

#include <deque>
#include <optional>
#include <vector>

#include "mapping/Registration.h"

namespace ambler::mapping {

// A walk's scans in the world frame, each registered by ICP against the one
// registered before it (bakambu-csa §2); the first is the reference. The
// chain only keeps the books: the caller runs each job where it likes (the
// Terrain mesh tab on a worker thread) and hands the result back.
class ScanChain {
 public:
  struct Job {
    Cloud source;  // the next scan, as dead reckoning placed it
    Cloud target;  // the last one registered
    ScannerOrigins scanners;
  };

  // Queued behind any other; `scanner` is where it was taken from, in the
  // same frame as its points.
  void add(Cloud scan, const Eigen::Vector3d& scanner);
  // The next registration to run, once none is under way; a first scan is
  // taken as the reference at once. None when nothing waits.
  std::optional<Job> next();
  // The result of the job next() gave: the scan joins the chain, moved by
  // the transform when the verdict lets it (applies); otherwise, and for a
  // registration that could not run (Registration{}), where dead reckoning
  // put it. The caller shows the verdict either way.
  void finish(const Registration& registration);
  // Trusted and doubtful corrections are applied; degenerate ones and
  // clouds that do not overlap are not.
  static bool applies(const Registration& registration);
  void clear();  // a job under way finishes into nothing

  bool busy() const { return in_flight_.has_value(); }
  std::size_t waiting() const { return waiting_.size(); }
  const std::vector<Cloud>& registered() const { return registered_; }
  Cloud merged() const;
  // The last scan's registration and the correction it applied.
  const Registration& last() const { return last_; }

  // Runs a job: ICP from the identity (the scans are already in the world
  // frame by dead reckoning); a registration that cannot run (too few
  // points) gives the identity, not converged.
  static Registration run(const Job& job, const RegistrationOptions& options = {});

 private:
  struct Scan {
    Cloud points;
    Eigen::Vector3d scanner;
  };
  std::deque<Scan> waiting_;
  std::optional<Scan> in_flight_;
  std::vector<Cloud> registered_;
  Eigen::Vector3d last_scanner_ = Eigen::Vector3d::Zero();  // of registered_.back()
  Registration last_;
};

}  // namespace ambler::mapping
