// WorkBudget (issue 49 item 2): all clients together hold at most the budget, one client at most
// its share; a refusal says which limit and how much of it is held; a reservation's bytes come
// back when its last copy goes, from any thread.
#include "server/services/work_budget.h"

#include <gtest/gtest.h>

#include <thread>
#include <vector>

#include "server/handlers/work_size.h"  // describe: a refusal in words

namespace sweepd::server {
namespace {

using Reserved = std::shared_ptr<const WorkReservation>;

TEST(WorkBudget, AClientPastItsShareIsRefusedWhileOthersStillFitTheBudget) {
  WorkBudget budget(1000, 600);
  auto first = budget.reserve(1, 500);
  ASSERT_TRUE(std::holds_alternative<Reserved>(first));
  const auto second = budget.reserve(1, 200);  // 700 of client 1's 600
  ASSERT_TRUE(std::holds_alternative<WorkRefusal>(second));
  const WorkRefusal refusal = std::get<WorkRefusal>(second);
  EXPECT_TRUE(refusal.over_share);
  EXPECT_EQ(refusal.bytes, 200u);
  EXPECT_EQ(refusal.limit, 600u);
  EXPECT_EQ(refusal.in_use, 500u);
  EXPECT_EQ(budget.refusals(), 1u);

  auto other = budget.reserve(2, 450);  // 950 of 1000 in all
  ASSERT_TRUE(std::holds_alternative<Reserved>(other));
  const auto third = budget.reserve(3, 100);  // 1050: the budget's limit, not a share
  ASSERT_TRUE(std::holds_alternative<WorkRefusal>(third));
  EXPECT_FALSE(std::get<WorkRefusal>(third).over_share);
  EXPECT_EQ(std::get<WorkRefusal>(third).in_use, 950u);
  EXPECT_EQ(budget.used(), 950u);

  first = WorkRefusal{};  // client 1's reservation gone: its bytes come back
  EXPECT_EQ(budget.used(), 450u);
  EXPECT_TRUE(std::holds_alternative<Reserved>(budget.reserve(1, 550)));
  EXPECT_EQ(budget.used(), 450u);  // that one was dropped at once
}

TEST(WorkBudget, WorkThatCouldNeverFitIsRefusedWhateverIsHeldAndCounted) {
  // A stream's frames (SubscribeStream): refused when asked if no frame could ever fit.
  WorkBudget budget(1000, 600);
  auto held = budget.reserve(1, 550);  // what is held does not matter to it
  EXPECT_FALSE(budget.refusal_whatever_is_held(600).has_value()) << "fits the share once free";
  const std::optional<WorkRefusal> past_share = budget.refusal_whatever_is_held(601);
  ASSERT_TRUE(past_share.has_value());
  EXPECT_TRUE(past_share->over_share);
  EXPECT_EQ(past_share->limit, 600u);
  EXPECT_EQ(past_share->in_use, 0u);
  WorkBudget share_above_budget(500, 600);
  const std::optional<WorkRefusal> past_budget = share_above_budget.refusal_whatever_is_held(501);
  ASSERT_TRUE(past_budget.has_value());
  EXPECT_FALSE(past_budget->over_share);
  EXPECT_EQ(past_budget->limit, 500u);
  EXPECT_EQ(budget.refusals(), 1u);
  EXPECT_EQ(share_above_budget.refusals(), 1u);
  EXPECT_EQ(budget.used(), 550u) << "nothing reserved";
}

TEST(WorkBudget, ARefusalNamesTheBytesTheLimitAndWhatIsHeld) {
  EXPECT_EQ(describe({1234567, false, 2000000, 1500000}),
            "needs 1,234,567 bytes of working memory, over what the server's work budget has "
            "free now (--work-budget-bytes 2,000,000, 1,500,000 held by all clients: 500,000 "
            "fit)");
  EXPECT_EQ(describe({700, true, 600, 0}),
            "needs 700 bytes of working memory, over this client's share of the server's work "
            "budget (--work-budget-client-bytes 600, 0 held by this client's requests now: 600 "
            "fit)");
}

// Eight threads reserve and give back at once: nothing is lost or counted twice, and the budget
// is never passed (every success fits what the others hold).
TEST(WorkBudget, ReservationsFromManyThreadsNeverPassTheBudgetAndAllComeBack) {
  WorkBudget budget(10'000, 10'000);
  std::vector<std::thread> threads;
  std::atomic<bool> passed{false};
  for (int t = 0; t < 8; ++t) {
    threads.emplace_back([&budget, &passed, t] {
      for (int i = 0; i < 2000; ++i) {
        const auto reserved = budget.reserve(static_cast<std::uint64_t>(t), 1000 + 37 * (i % 50));
        if (budget.used() > budget.limit()) passed = true;
      }
    });
  }
  for (std::thread& thread : threads) thread.join();
  EXPECT_FALSE(passed);
  EXPECT_EQ(budget.used(), 0u);
}

}  // namespace
}  // namespace sweepd::server
