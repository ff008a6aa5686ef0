#include "link/dds/DdsEntity.h"

#include <cstdlib>
#include <map>
#include <memory>
#include <mutex>

#include "AmblerLink.h"
#include "link/Link.h"

namespace ambler::link::dds {

namespace {

const char* kLoopbackConfig = R"(<CycloneDDS xmlns="https://cdds.io/config"><Domain Id="any">
  <General><Interfaces><NetworkInterface address="127.0.0.1" multicast="false"/></Interfaces>
    <AllowMulticast>false</AllowMulticast></General>
  <Discovery><ParticipantIndex>auto</ParticipantIndex>
    <MaxAutoParticipantIndex>32</MaxAutoParticipantIndex>
    <Peers><Peer address="127.0.0.1"/></Peers></Discovery>
</Domain></CycloneDDS>)";

// A domain is created once per process and kept until it exits: links and
// rover endpoints in one process (tests) share it.
void ensureDomain(std::uint32_t domain) {
  static std::mutex mutex;
  static std::map<std::uint32_t, dds_entity_t> domains;
  std::lock_guard lock(mutex);
  if (domains.count(domain)) return;
  const char* uri = std::getenv("CYCLONEDDS_URI");
  const dds_entity_t d = dds_create_domain(domain, uri && *uri ? uri : kLoopbackConfig);
  if (d < 0 && d != DDS_RETCODE_PRECONDITION_NOT_MET)
    check(d, "creating DDS domain " + std::to_string(domain) +
                 (uri && *uri ? std::string(" from CYCLONEDDS_URI=") + uri : ""));
  domains[domain] = d;
}

struct Qos {
  explicit Qos(Traffic traffic) : qos(dds_create_qos()) {
    dds_qset_reliability(qos, DDS_RELIABILITY_RELIABLE, DDS_SECS(1));
    switch (traffic) {
      case Traffic::kState:
        dds_qset_durability(qos, DDS_DURABILITY_TRANSIENT_LOCAL);
        dds_qset_history(qos, DDS_HISTORY_KEEP_LAST, 1);
        break;
      case Traffic::kImages:
        dds_qset_durability(qos, DDS_DURABILITY_TRANSIENT_LOCAL);
        dds_qset_history(qos, DDS_HISTORY_KEEP_LAST, 4);
        break;
      case Traffic::kAnswers:
        dds_qset_durability(qos, DDS_DURABILITY_TRANSIENT_LOCAL);
        dds_qset_history(qos, DDS_HISTORY_KEEP_LAST, 64);
        // What a late reader gets: Cyclone keeps only the last sample by
        // default.
        dds_qset_durability_service(qos, 0, DDS_HISTORY_KEEP_LAST, 64, DDS_LENGTH_UNLIMITED,
                                    DDS_LENGTH_UNLIMITED, DDS_LENGTH_UNLIMITED);
        break;
      case Traffic::kCommands:
        dds_qset_durability(qos, DDS_DURABILITY_VOLATILE);
        dds_qset_history(qos, DDS_HISTORY_KEEP_LAST, 64);
        break;
    }
  }
  ~Qos() { dds_delete_qos(qos); }
  dds_qos_t* qos;
};

Entity topic(dds_entity_t participant, const dds_topic_descriptor_t& desc, const char* name) {
  return Entity(dds_create_topic(participant, &desc, name, nullptr, nullptr),
                std::string("creating topic ") + name);
}

}  // namespace

dds_return_t check(dds_return_t rc, const std::string& what) {
  if (rc < 0) throw LinkError(what + ": " + dds_strretcode(rc));
  return rc;
}

Entity joinDomain(std::uint32_t domain) {
  if (domain > 232) throw LinkError("DDS domain " + std::to_string(domain) + " is not in 0..232");
  ensureDomain(domain);
  return Entity(dds_create_participant(domain, nullptr, nullptr),
                "joining DDS domain " + std::to_string(domain));
}

Topics::Topics(dds_entity_t p)
    : heartbeat(topic(p, ambler_dds_Heartbeat_desc, "ambler/Heartbeat")),
      leg_state(topic(p, ambler_dds_LegState_desc, "ambler/LegState")),
      body_state(topic(p, ambler_dds_BodyState_desc, "ambler/BodyState")),
      command_ack(topic(p, ambler_dds_CommandAck_desc, "ambler/CommandAck")),
      range_image(topic(p, ambler_dds_RangeImage_desc, "ambler/RangeImage")),
      striper_image(topic(p, ambler_dds_StriperImage_desc, "ambler/StriperImage")),
      command(topic(p, ambler_dds_Command_desc, "ambler/Command")) {}

Entity makeWriter(dds_entity_t participant, dds_entity_t topic, Traffic traffic) {
  const Qos q(traffic);
  return Entity(dds_create_writer(participant, topic, q.qos, nullptr), "creating a DDS writer");
}

Entity makeReader(dds_entity_t participant, dds_entity_t topic, Traffic traffic) {
  const Qos q(traffic);
  return Entity(dds_create_reader(participant, topic, q.qos, nullptr), "creating a DDS reader");
}

}  // namespace ambler::link::dds
