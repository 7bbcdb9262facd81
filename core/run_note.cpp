// See run_note.hpp.
#include "core/run_note.hpp"

#include <algorithm>

namespace rover {

namespace {

void replace_all(std::string& text, const std::string& from, const std::string& to) {
  for (std::size_t at = text.find(from); at != std::string::npos; at = text.find(from, at + to.size()))
    text.replace(at, from.size(), to);
}

}  // namespace

std::string run_note(std::string kind, std::string details) {
  replace_all(kind, kNoteSeparator, ", ");
  replace_all(details, kNoteSeparator, ", ");
  replace_all(kind, kNoteKindEnd, " ");
  replace_all(kind, kNoteDetailsOpen, " ");
  return kind + kNoteKindEnd + details;
}

std::string join_notes(const std::vector<std::string>& notes) {
  std::string message;
  for (const std::string& note : notes)
    if (!note.empty()) message += (message.empty() ? "" : kNoteSeparator) + note;
  return message;
}

std::vector<std::string> split_notes(const std::string& message) {
  std::vector<std::string> notes;
  const std::string separator = kNoteSeparator;
  for (std::size_t begin = 0; begin <= message.size();) {
    const std::size_t end = std::min(message.find(separator, begin), message.size());
    if (end > begin) notes.push_back(message.substr(begin, end - begin));
    begin = end + separator.size();
  }
  return notes;
}

std::string note_kind(const std::string& note) {
  return note.substr(0, std::min(note.find(kNoteKindEnd), note.find(kNoteDetailsOpen)));
}

}  // namespace rover
