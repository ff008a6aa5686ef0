#include "app/gs/DdsConnection.h"

#include "link/dds/DdsMessages.h"
#include "missionlog/ReplayLinks.h"

namespace ambler::gs {

RoverConnection ddsConnection(std::uint32_t domain, std::uint32_t rover_id,
                              const std::filesystem::path& key_file) {
  RoverConnection c;
  c.key = link::readOperatorKey(key_file);
  // Made now, so that a domain that cannot be joined is refused at once.
  auto link = std::make_shared<std::unique_ptr<link::Link>>(
      std::make_unique<link::dds::DdsLink>(domain, rover_id));
  c.description = (*link)->describe();
  c.open = [link] { return std::move(*link); };
  c.rover_id = rover_id;
  c.first_sequence = missionlog::firstSequenceFromClock();
  c.mission = "ambler-gs walk of rover " + std::to_string(rover_id) + " on DDS domain " +
              std::to_string(domain);
  return c;
}

}  // namespace ambler::gs
