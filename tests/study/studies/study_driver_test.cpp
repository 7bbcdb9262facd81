// The counts a study reports after its runs (study/studies/study_driver.hpp):
// failed runs, and runs that finished with notes, counted per kind of note,
// one line per kind with its first example.
#include "study/studies/study_driver.hpp"

#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/run_note.hpp"
#include "study/runtime/run_record.hpp"

namespace rover::study {
namespace {

TEST(CountRuns, NotesAreCountedPerKindAndARunWithTwoCountsUnderBoth) {
  const std::string friction_a = run_note("the friction law misses its parameters", "peak mu 0.41");
  const std::string friction_b = run_note("the friction law misses its parameters", "peak mu 0.57");
  const std::string ground = run_note("no wheel touched the ground", "within the run's 0.3 s");
  const int ok = run_status::kOk;
  const std::vector<int> status{ok, ok, ok, 1, ok, ok};
  const std::vector<std::string> messages{friction_a, "", join_notes({friction_b, ground}), "diverged", ground, ""};
  const RunCounts c = count_runs(status, messages);
  EXPECT_EQ(c.runs, 6);
  EXPECT_EQ(c.failed, 1);
  EXPECT_EQ(c.first_failure, "diverged");
  EXPECT_EQ(c.noted, 3);
  ASSERT_EQ(c.notes.size(), 2u);
  EXPECT_EQ(c.notes[0].kind, "the friction law misses its parameters");
  EXPECT_EQ(c.notes[0].runs, 2);
  EXPECT_EQ(c.notes[0].first, friction_a);
  EXPECT_EQ(c.notes[1].kind, "no wheel touched the ground");
  EXPECT_EQ(c.notes[1].runs, 2);
  EXPECT_EQ(c.notes[1].first, ground);
  const std::vector<std::string> lines = note_lines(c);
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_EQ(lines[0], "2 of 6 runs finished, but " + friction_a + " (the first of them)");
  EXPECT_EQ(lines[1], "2 of 6 runs finished, but " + ground + " (the first of them)");
}

TEST(CountRuns, OneLinePerKindUpToALimit) {
  std::vector<int> status;
  std::vector<std::string> messages;
  for (std::size_t k = 0; k < kNoteKindsPrinted + 3; ++k) {
    status.push_back(run_status::kOk);
    messages.push_back(run_note("problem " + std::to_string(k), "details"));
  }
  const std::vector<std::string> lines = note_lines(count_runs(status, messages));
  ASSERT_EQ(lines.size(), kNoteKindsPrinted + 1);
  EXPECT_EQ(lines[0], "1 of " + std::to_string(status.size()) + " runs finished, but problem 0: details");
  EXPECT_EQ(lines.back(), "3 more kinds of note; every run's notes are in the results (/samples/message)");
  EXPECT_TRUE(note_lines(count_runs({run_status::kOk}, {""})).empty());
}

}  // namespace
}  // namespace rover::study
