#include "link/CommandAuthority.h"

#include <gtest/gtest.h>

namespace ambler::link {
namespace {

Command from(const std::string& op, std::uint64_t console, CommandBody body) {
  Command c;
  c.operator_id = op, c.console_id = console, c.body = std::move(body);
  return c;
}

const std::string kAlice = consoleName("alice", 1), kBob = consoleName("bob", 2);

TEST(CommandAuthority, TheFirstConsoleToCommandTakesItAndNoOtherCanMoveTheRover) {
  CommandAuthority authority;
  std::string change;
  EXPECT_FALSE(authority.admit(from("alice", 1, BodyMove{}), change).refused());
  EXPECT_EQ(change, kAlice + " took command authority");
  EXPECT_EQ(authority.holder(), kAlice);
  for (const CommandBody& motion :
       {CommandBody{BodyMove{}}, CommandBody{LegMove{}}, CommandBody{Resume{}},
        CommandBody{AcquireScan{}}, CommandBody{Grasp{}}}) {
    const auto refused = authority.admit(from("bob", 2, motion), change);
    EXPECT_EQ(refused.why(), kBob + " does not hold command authority (" + kAlice +
                                 " does): send RequestAuthority and wait for a hand-over");
  }
  // The same operator at another console is another console.
  EXPECT_TRUE(authority.admit(from("alice", 3, BodyMove{}), change).refused());
  // Anyone authenticated may stop the rover.
  EXPECT_FALSE(authority.admit(from("bob", 2, Hold{}), change).refused());
  EXPECT_FALSE(authority.admit(from("bob", 2, GroundHeartbeat{}), change).refused());
  EXPECT_EQ(authority.holder(), kAlice);
}

TEST(CommandAuthority, AHandOverIsAnExchangeTheHolderCompletes) {
  CommandAuthority authority;
  std::string change;
  ASSERT_FALSE(authority.admit(from("alice", 1, RequestAuthority{}), change).refused());
  EXPECT_EQ(change, kAlice + " took command authority");

  EXPECT_EQ(authority.admit(from("alice", 1, HandOver{kBob}), change).why(),
            "hand-over to " + kBob + ": no console has asked");
  ASSERT_FALSE(authority.admit(from("bob", 2, RequestAuthority{}), change).refused());
  EXPECT_EQ(change, kBob + " asks " + kAlice + " for command authority");
  EXPECT_EQ(authority.holder(), kAlice);
  EXPECT_EQ(authority.request(), kBob);
  // Only the holder hands over, and only to the console asking.
  EXPECT_EQ(authority.admit(from("bob", 2, HandOver{kBob}), change).why(),
            "only the console holding command authority (" + kAlice + ") can hand it over");
  EXPECT_TRUE(
      authority.admit(from("alice", 1, HandOver{consoleName("carol", 4)}), change).refused());

  ASSERT_FALSE(authority.admit(from("alice", 1, HandOver{kBob}), change).refused());
  EXPECT_EQ(change, kAlice + " handed command authority to " + kBob);
  EXPECT_EQ(authority.holder(), kBob);
  EXPECT_TRUE(authority.request().empty());
  EXPECT_TRUE(authority.admit(from("alice", 1, BodyMove{}), change).refused());
  EXPECT_FALSE(authority.admit(from("bob", 2, BodyMove{}), change).refused());
}

TEST(CommandAuthority, ItLapsesWithTheHoldersLinkAndTheNextConsoleTakesIt) {
  CommandAuthority authority;
  std::string change;
  ASSERT_FALSE(authority.admit(from("alice", 1, BodyMove{}), change).refused());
  EXPECT_EQ(authority.lapse(), "");
  EXPECT_FALSE(authority.held());
  EXPECT_FALSE(authority.admit(from("bob", 2, Resume{}), change).refused());
  EXPECT_EQ(authority.holder(), kBob);
  // A console that asked before the holder went silent has it then.
  ASSERT_FALSE(authority.admit(from("alice", 1, RequestAuthority{}), change).refused());
  EXPECT_EQ(authority.lapse(), kAlice + " took command authority (it had asked)");
  EXPECT_EQ(authority.holder(), kAlice);
}

}  // namespace
}  // namespace ambler::link
