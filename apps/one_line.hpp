#pragma once
// Every message of the tool is one line on standard error (scripts read the last line, and
// `2>&1 | tail -1` must show the whole reason). Paths and values come from the user and may
// hold a newline or other control characters: they are written escaped, as C would ("\n",
// "\t", "\x1b"). Only the message is escaped: the files keep their real names.

#include <cstdio>
#include <string>

namespace rgbmesh::cli {

inline std::string one_line(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (const char c : text) {
    const auto u = static_cast<unsigned char>(c);
    if (c == '\n') {
      out += "\\n";
    } else if (c == '\t') {
      out += "\\t";
    } else if (c == '\r') {
      out += "\\r";
    } else if (u < 0x20 || u == 0x7f) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\x%02x", u);
      out += buf;
    } else {
      out += c;
    }
  }
  return out;
}

}  // namespace rgbmesh::cli
