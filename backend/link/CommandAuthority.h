#pragma once

// Which console may command the rover. Any number of consoles may watch;
// exactly one holds command authority. The first console to send a command
// that needs it (needsAuthority) takes it when no console holds it; after
// that it changes hands only by an explicit exchange: the new console asks
// (RequestAuthority), the holder hands over (HandOver naming it). HOLD is
// accepted from any authenticated console. Authority lapses when the holder
// falls silent for the rover's link timeout (the rover then holds for a
// lost link, or holds already), to a console that asked for it if one did.

#include <string>

#include "core/Refusal.h"
#include "link/Messages.h"

namespace ambler::link {

class CommandAuthority {
 public:
  // For a command already verified (Signing.h): may it be carried out? An
  // accepted RequestAuthority or HandOver has then changed who holds it;
  // `change` says how, for the rover's log ("alice@... took command
  // authority", ...), or stays empty.
  [[nodiscard]] Refusal admit(const Command& command, std::string& change);
  // The holder's link was lost: a console that had asked now holds it
  // (the rover holds, so it must still Resume), else none does. Returns
  // that change, or empty.
  std::string lapse();

  bool held() const { return !holder_.empty(); }
  // consoleName()s; empty: none.
  const std::string& holder() const { return holder_; }
  const std::string& request() const { return request_; }

 private:
  std::string holder_, request_;
};

}  // namespace ambler::link
