#include "link/CommandAuthority.h"

namespace ambler::link {

Refusal CommandAuthority::admit(const Command& c, std::string& change) {
  change.clear();
  const std::string from = consoleName(c.operator_id, c.console_id);
  if (std::holds_alternative<RequestAuthority>(c.body)) {
    if (holder_ == from) return {};
    if (holder_.empty()) {
      holder_ = from, request_.clear();
      change = from + " took command authority";
    } else {
      request_ = from;
      change = from + " asks " + holder_ + " for command authority";
    }
    return {};
  }
  if (const auto* h = std::get_if<HandOver>(&c.body)) {
    if (holder_ != from)
      return Refusal::because("only the console holding command authority (" +
                              (holder_.empty() ? std::string("none") : holder_) +
                              ") can hand it over");
    if (h->console.empty() || h->console != request_)
      return Refusal::because("hand-over to " + (h->console.empty() ? "nobody" : h->console) +
                              ": " +
                              (request_.empty() ? std::string("no console has asked")
                                                : request_ + " is the one asking"));
    holder_ = std::exchange(request_, {});
    change = from + " handed command authority to " + holder_;
    return {};
  }
  if (!needsAuthority(c.body)) return {};
  if (holder_.empty()) {
    holder_ = from;
    change = from + " took command authority";
    if (request_ == from) request_.clear();
    return {};
  }
  if (holder_ != from)
    return Refusal::because(from + " does not hold command authority (" + holder_ +
                            " does): send RequestAuthority and wait for a hand-over");
  return {};
}

std::string CommandAuthority::lapse() {
  holder_ = std::exchange(request_, {});
  return holder_.empty() ? std::string() : holder_ + " took command authority (it had asked)";
}

}  // namespace ambler::link
