#include "app/gs/DdsConnection.h"

#include "link/dds/DdsMessages.h"

namespace ambler::gs {

RoverConnection ddsConnection(std::uint32_t domain, std::uint32_t rover_id,
                              const std::filesystem::path& key_file) {
  RoverConnection c;
  c.key = link::readOperatorKey(key_file);
  c.link = std::make_unique<link::dds::DdsLink>(domain, rover_id);
  c.rover_id = rover_id;
  c.first_sequence = missionlog::firstSequenceFromClock();
  c.mission = "ambler-gs walk of rover " + std::to_string(rover_id) + " on DDS domain " +
              std::to_string(domain);
  return c;
}

}  // namespace ambler::gs
