// See interruptible_outputs.hpp.
#include "drivers/interruptible_outputs.hpp"

#include <algorithm>

namespace rover::cli {
namespace {

std::string joined(const std::vector<std::string>& paths) {
  std::string text;
  for (const std::string& path : paths) text += (text.empty() ? "" : ", ") + path;
  return text;
}

}  // namespace

InterruptibleOutputs::InterruptibleOutputs(const std::vector<std::string>& planned) {
  for (const std::string& path : planned)
    if (!path.empty()) planned_.push_back(path);
}

void InterruptibleOutputs::written(const std::string& path) {
  written_.push_back(path);
  stop_if_signalled();
}

void InterruptibleOutputs::dropped(const std::string& path) { std::erase(planned_, path); }

void InterruptibleOutputs::stop_if_signalled() const {
  if (signalled()) interrupted("");
}

void InterruptibleOutputs::interrupted_while(const std::string& activity) const {
  interrupted(" while " + activity);
}

void InterruptibleOutputs::interrupted(const std::string& during) const {
  std::vector<std::string> unwritten;
  for (const std::string& path : planned_)
    if (std::find(written_.begin(), written_.end(), path) == written_.end()) unwritten.push_back(path);
  std::string what = written_.empty() ? "nothing written" : "wrote " + joined(written_);
  if (!unwritten.empty() && !written_.empty()) what += "; not written: " + joined(unwritten);
  if (!unwritten.empty()) what += " (an earlier file at such a path is left as it was)";
  if (unwritten.empty() && !written_.empty()) what += " in full before the signal took effect";
  throw study::StudyInterrupted("interrupted (" + study::InterruptGuard::signal_name() + ")" + during + "; " + what);
}

}  // namespace rover::cli
