// A standby's standing commands: what it holds of the commands it read, once the coordinator it follows
// has answered them.
#include <gtest/gtest.h>

#include "standing_commands.hpp"

namespace lpss::coordinator {
namespace {

wire::Command command(const std::string& client, std::uint64_t request) {
    wire::Command c;
    c.client(client);
    c.request(request);
    c.kind(wire::kCommandSetVelocity);
    return c;
}

TEST(StandingCommands, ARunAnsweredAtOnceForgetsEveryCommandOfItHoweverLong) {
    // A flood is refused for the rate in runs of thousands, each answered once. Before the run was looked up
    // by range, only its newest 4,096 were forgotten: a standby beside a flood of 10^5 commands a second
    // grew by 8 MiB in 3 s and kept them until it took over.
    StandingCommands standing;
    const std::uint64_t run = 3 * StandingCommands::kMostEarlyAnswers;
    for (std::uint64_t r = 1; r <= run; ++r)
        standing.add(command("flooder", r));
    standing.add(command("other", 1));
    standing.forget("flooder", 1, run);
    ASSERT_EQ(standing.size(), 1u);
    EXPECT_EQ(standing.take_all().front().client(), "other");
}

TEST(StandingCommands, AnAnswerThatCameFirstKeepsItsCommandOut) {
    StandingCommands standing;
    standing.forget("client", 5, 7);
    standing.add(command("client", 6));
    standing.add(command("client", 8));
    standing.add(command("client", 5));
    const std::vector<wire::Command> left = standing.take_all();
    ASSERT_EQ(left.size(), 1u);
    EXPECT_EQ(left.front().request(), 8u);
    EXPECT_EQ(standing.size(), 0u);
}

TEST(StandingCommands, OnlyTheNewestEarlyAnswersOfALongRunAreRemembered) {
    // Answers for commands not read yet are bounded: of a run longer than that, its oldest are forgotten,
    // and such a command read later stands (the coordinator that takes over answers it again).
    StandingCommands standing;
    const std::uint64_t run = 2 * StandingCommands::kMostEarlyAnswers;
    standing.forget("client", 1, run);
    standing.add(command("client", run));
    EXPECT_EQ(standing.size(), 0u);
    standing.add(command("client", 1));
    EXPECT_EQ(standing.size(), 1u);
}

TEST(StandingCommands, ACommandReadTwiceStandsOnce) {
    StandingCommands standing;
    standing.add(command("client", 1));
    standing.add(command("client", 1));
    EXPECT_EQ(standing.size(), 1u);
    EXPECT_EQ(standing.newest().at("client"), 1u);
}

}  // namespace
}  // namespace lpss::coordinator
