#pragma once

// The link's messages on DDS: writers and readers for every topic, with the
// conversion between the IDL types and link/Messages.h. Whatever arrives is
// checked by the same rules as the byte codec before anyone sees it.

#include <chrono>
#include <string>
#include <vector>

#include "link/Link.h"
#include "link/Messages.h"
#include "link/dds/DdsEntity.h"

namespace ambler::link::dds {

// Waits until one of the attached readers has data, or the timeout.
class DataWait {
 public:
  explicit DataWait(dds_entity_t participant);
  void attach(dds_entity_t reader);
  void wait(std::chrono::milliseconds timeout) const;

 private:
  Entity waitset_;
};

// The rover's side: telemetry out, commands in.
class RoverEndpoint {
 public:
  RoverEndpoint(std::uint32_t domain, std::uint32_t rover_id);
  void publish(const Telemetry& message);
  // Commands addressed to this rover, in the order sent. A command that
  // arrives malformed comes back as one with no body check passed:
  // `malformed` holds its problem, to be NACKed.
  struct Received {
    Command command;
    std::string malformed;
  };
  std::vector<Received> takeCommands(std::chrono::milliseconds timeout);

 private:
  std::uint32_t rover_id_;
  Entity participant_;
  Topics topics_;
  Entity heartbeat_, leg_state_, body_state_, command_ack_, range_image_, striper_image_, commands_;
  DataWait wait_;
};

// The console's side: a link to a rover, or ambler-sim, over DDS.
class DdsLink : public Link {
 public:
  // `discovery_wait`: how long a command waits for the rover's reader to
  // be matched; over a long-delay link discovery takes several round trips.
  DdsLink(std::uint32_t domain, std::uint32_t rover_id,
          std::chrono::milliseconds discovery_wait = std::chrono::seconds(2));
  // Throws LinkError when no rover has listened on the domain for the
  // discovery wait.
  void send(const Command& command) override;
  // Telemetry from this rover, in rover time order; malformed samples are
  // dropped and counted.
  std::vector<Telemetry> receive(std::chrono::milliseconds timeout) override;
  std::string describe() const override;
  long dropped() const { return dropped_; }

 private:
  template <typename Sample, typename Convert>
  void takeFrom(dds_entity_t reader, Convert&& convert, std::vector<Telemetry>& out);
  void waitForRover() const;

  std::uint32_t domain_, rover_id_;
  std::chrono::milliseconds discovery_wait_;
  Entity participant_;
  Topics topics_;
  Entity heartbeat_, leg_state_, body_state_, command_ack_, range_image_, striper_image_, commands_;
  DataWait wait_;
  long dropped_ = 0;
};

}  // namespace ambler::link::dds
