#pragma once

#include "core/Refusal.h"
#include "gait/GaitPlanner.h"
#include "link/Messages.h"

namespace ambler::link {

// The first way `command` exceeds the rover's kinematic limits (joint
// ranges, body advance and turn per move), as a sentence for an operator or
// a NACK; not refused when within them. The ground checks before sending,
// the rover again before moving.
Refusal outsideLimits(const CommandBody& command, const gait::RoverModel& model,
                      const gait::GaitOptions& gait);

}  // namespace ambler::link
