#pragma once

// Small RAII helpers over Cyclone DDS's C API (Debian ships no C++ binding,
// ../shared/STACK.md).

#include <dds/dds.h>

#include <stdexcept>
#include <string>
#include <utility>

namespace ambler::link::dds {

// Throws LinkError naming `what` when `rc` is a DDS error code.
dds_return_t check(dds_return_t rc, const std::string& what);

// A DDS entity deleted (with its children) when this goes.
class Entity {
 public:
  Entity() = default;
  explicit Entity(dds_entity_t handle, const std::string& what) : handle_(check(handle, what)) {}
  Entity(Entity&& other) noexcept : handle_(std::exchange(other.handle_, 0)) {}
  Entity& operator=(Entity&& other) noexcept {
    std::swap(handle_, other.handle_);
    return *this;
  }
  Entity(const Entity&) = delete;
  Entity& operator=(const Entity&) = delete;
  ~Entity() {
    if (handle_ > 0) dds_delete(handle_);
  }
  dds_entity_t get() const { return handle_; }

 private:
  dds_entity_t handle_ = 0;
};

// A participant on `domain` (0-232). By default configured for loopback
// only, unicast, as STACK.md prescribes: a process and its tests never touch
// the network. With CYCLONEDDS_URI set (a file:// URI or an XML fragment),
// that configuration is used instead: how a console reaches a real rover
// (docs/dds.md).
Entity joinDomain(std::uint32_t domain);

// The link's topics on one participant, with their QoS: state
// (heartbeat, legs, body, images) reliable and transient-local so that a
// console joining late gets the latest; acknowledgements reliable, in
// order and transient-local (the last 64), so that one written before the
// rover's writer had matched a console's reader still reaches it; commands
// reliable, in order and volatile.
struct Topics {
  explicit Topics(dds_entity_t participant);
  Entity heartbeat, leg_state, body_state, command_ack, range_image, striper_image, command;
};

// Reader and writer QoS for a topic of `Topics`.
enum class Traffic { kState, kImages, kAnswers, kCommands };
Entity makeWriter(dds_entity_t participant, dds_entity_t topic, Traffic traffic);
Entity makeReader(dds_entity_t participant, dds_entity_t topic, Traffic traffic);

}  // namespace ambler::link::dds
