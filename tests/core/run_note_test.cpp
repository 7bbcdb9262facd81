// Notes on finished runs (core/run_note.hpp): "<kind>: <details>", joined
// with "; ", read back note by note with their kinds, also for notes whose
// parts hold a separator and for notes written as "<kind> (<details>)".
#include "core/run_note.hpp"

#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace rover {
namespace {

TEST(RunNote, NotesJoinAndSplitBackWithTheirKinds) {
  const std::string a = run_note("no wheel touched the ground", "within the run's 0.3 s, B_l z went from 1 to 0.5 m");
  const std::string b = run_note("the friction law misses its parameters", "peak mu 0.4 (mu_k above mu_s?)");
  EXPECT_EQ(a, "no wheel touched the ground: within the run's 0.3 s, B_l z went from 1 to 0.5 m");
  const std::string message = join_notes({a, "", b});
  EXPECT_EQ(message, a + "; " + b);
  EXPECT_EQ(split_notes(message), (std::vector<std::string>{a, b}));
  EXPECT_EQ(note_kind(a), "no wheel touched the ground");
  EXPECT_EQ(note_kind(b), "the friction law misses its parameters");
  EXPECT_TRUE(split_notes("").empty());
  EXPECT_EQ(join_notes({"", ""}), "");
}

TEST(RunNote, SeparatorsInsideANoteAreReplacedSoItReadsBack) {
  // A QoI label with ": " and "; " in a kind, a "; " in the details.
  const std::string note = run_note("my: at_rest; label (B) is no rest height", "still moving; lengthen it");
  ASSERT_EQ(split_notes(note).size(), 1u) << note;
  EXPECT_EQ(note_kind(note), "my at_rest, label B) is no rest height");
  EXPECT_EQ(note.substr(note_kind(note).size()), ": still moving, lengthen it");
}

TEST(RunNote, ANoteWithItsDetailsInParenthesesHasItsLeadingWordsAsKind) {
  EXPECT_EQ(note_kind("the friction law misses its parameters (Makkar fit RMS 0.004): mu_k above mu_s"),
            "the friction law misses its parameters");
  EXPECT_EQ(note_kind("a note without details"), "a note without details");
}

}  // namespace
}  // namespace rover
