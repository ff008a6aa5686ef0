#pragma once

#include <optional>
#include <string>
#include <utility>

namespace ambler {

// What an action that may be refused returns: nothing when it was done,
// else why not, in a sentence an operator can read. The type is
// [[nodiscard]], so that no caller drops a refusal silently.
class [[nodiscard]] Refusal {
 public:
  Refusal() = default;  // done
  static Refusal because(std::string why) {
    Refusal r;
    r.why_ = why.empty() ? std::string("refused") : std::move(why);
    return r;
  }
  bool refused() const { return why_.has_value(); }
  // Why not; empty when done.
  const std::string& why() const {
    static const std::string none;
    return why_ ? *why_ : none;
  }

 private:
  std::optional<std::string> why_;
};

}  // namespace ambler
