// causal-estimator's resend list (services/causal_estimator/unacked_output.hpp): every condition-level message stays
// listed until it was written AND the readers acknowledged everything afterwards; the list is bounded by snapshots.
#include "unacked_output.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace causal::estimator {
namespace {

using Strings = std::vector<std::string>;

TEST(UnackedOutput, QueuedSnapshotsStayListedUntilWrittenAndAcknowledged) {
  UnackedOutput u;
  std::vector<UnackedOutput::Flag> flags;
  for (int s = 0; s < 3; ++s) {  // three snapshots' output queued behind a writer that waits
    u.begin_snapshot();
    flags.push_back(u.add("C" + std::to_string(s)));
    flags.push_back(u.add("B" + std::to_string(s)));
  }
  int asked = 0;
  u.settle([&] { return ++asked, true; });
  EXPECT_EQ(asked, 0);  // nothing written yet: nothing to ask about
  EXPECT_EQ(u.list(), (Strings{"C0", "B0", "C1", "B1", "C2", "B2"}));
  flags[0]->store(true);
  flags[1]->store(true);
  flags[2]->store(true);
  u.settle([] { return false; });  // written, not acknowledged (a reader is behind or dead): kept
  EXPECT_EQ(u.list(), (Strings{"C0", "B0", "C1", "B1", "C2", "B2"}));
  u.settle([] { return true; });
  EXPECT_EQ(u.list(), (Strings{"B1", "C2", "B2"}));  // what was not written stays, in order
  EXPECT_EQ(u.messages(), 3u);
  for (auto& f : flags) f->store(true);
  u.settle([] { return true; });
  EXPECT_TRUE(u.list().empty());
  EXPECT_EQ(u.dropped(), 0u);
}

TEST(UnackedOutput, AWriteDuringTheQuestionIsNotForgotten) {
  UnackedOutput u;
  u.begin_snapshot();
  auto a = u.add("C0");
  auto b = u.add("B0");
  a->store(true);
  // b is written while the readers are asked: the answer may not cover it, so it stays.
  u.settle([&] { b->store(true); return true; });
  EXPECT_EQ(u.list(), (Strings{"B0"}));
}

TEST(UnackedOutput, BoundedByTheBacklogInSnapshotsAndCountsWhatLeaves) {
  UnackedOutput u;
  const std::size_t n = UnackedOutput::kMaxSnapshots + 5;
  for (std::size_t s = 0; s < n; ++s) {
    u.begin_snapshot();
    u.add("C" + std::to_string(s));
    u.add("B" + std::to_string(s));
  }
  EXPECT_EQ(u.messages(), 2 * UnackedOutput::kMaxSnapshots);
  EXPECT_EQ(u.dropped(), 2u * 5u);  // the oldest whole snapshots (0..4) left as 600..604 began
  EXPECT_EQ(u.list().front(), "C5");
  EXPECT_EQ(u.list().back(), "B" + std::to_string(n - 1));
}

TEST(UnackedOutput, ASnapshotWithoutOutputTakesNoPlace) {
  UnackedOutput u;
  for (std::size_t s = 0; s < 2 * UnackedOutput::kMaxSnapshots; ++s) u.begin_snapshot();
  u.add("C0");
  EXPECT_EQ(u.list(), (Strings{"C0"}));
  EXPECT_EQ(u.dropped(), 0u);
}

}  // namespace
}  // namespace causal::estimator
