// The registry of named scales: every name with the numbers the commands used before it existed
// (the golden files and the shipped models depend on them), and unknown names refused.
#include <gtest/gtest.h>

#include "data/scales.h"

namespace quadfdi {
namespace {

TEST(Scales, EveryNameHasItsDataScheduleAndEvaluationSize) {
  EXPECT_EQ(scaleNames(), (std::vector<std::string>{"tiny", "quick", "default", "paper"}));
  struct Expected {
    const char* name;
    const char* data_name;
    int n1;
    std::size_t buffer;
    int batch, passes, max_minibatches, min_iterations, max_iterations, heldout, flights;
  };
  const Expected expected[] = {
      {"tiny", "tiny", 4, 20'000, 256, 1, 8, 1, 2, 1, 3},
      {"quick", "default", 40, 200'000, 512, 1, 40, 5, 5, 5, 25},
      {"default", "default", 40, 200'000, 512, 1, 60, 10, 16, 20, 200},
      {"paper", "paper", 100, 1'500'000, 50'000, 400, 0, 250, 500, 20, 2000},
  };
  for (const Expected& e : expected) {
    const NamedScale* s = findScale(e.name);
    ASSERT_NE(s, nullptr) << e.name;
    EXPECT_EQ(s->name, e.name);
    EXPECT_EQ(s->data.name, e.data_name) << e.name;
    EXPECT_EQ(s->data.initial_conditions, e.n1) << e.name;
    EXPECT_EQ(s->data.buffer_windows, e.buffer) << e.name;
    EXPECT_EQ(s->training.batch_size, e.batch) << e.name;
    EXPECT_EQ(s->training.passes, e.passes) << e.name;
    EXPECT_EQ(s->training.max_minibatches, e.max_minibatches) << e.name;
    EXPECT_EQ(s->training.min_iterations, e.min_iterations) << e.name;
    EXPECT_EQ(s->training.max_iterations, e.max_iterations) << e.name;
    EXPECT_EQ(s->training.heldout_initial_conditions, e.heldout) << e.name;
    EXPECT_EQ(s->test_flights_per_class, e.flights) << e.name;
  }
}

TEST(Scales, UnknownNamesAreRefusedListingTheKnownOnes) {
  for (const char* name : {"huge", "", "Paper", "default "}) {
    std::string problem;
    EXPECT_EQ(findScale(name, &problem), nullptr) << name;
    EXPECT_EQ(problem, "unknown scale '" + std::string(name) + "' (known: tiny, quick, default, paper)");
  }
  EXPECT_EQ(findScale("huge"), nullptr);  // no message asked for
}

}  // namespace
}  // namespace quadfdi
