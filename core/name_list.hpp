// Names listed in a message or a report line: "c_q, f, M0".
#pragma once

#include <string>
#include <vector>

namespace rover {

inline std::string comma_separated(const std::vector<std::string>& names) {
  std::string list;
  for (const std::string& name : names) list += (list.empty() ? "" : ", ") + name;
  return list;
}

}  // namespace rover
