// The encoding and line ends of text inputs. JSON configs and CSV curves are UTF-8 (RFC 8259,
// section 8.1); a file saved as UTF-16 or UTF-32, as some Windows editors do,
// holds NUL bytes and would otherwise reach the parsers as garbled names.
#pragma once

#include <string>
#include <string_view>

namespace rover::io {

// What is wrong with `text` as UTF-8 text ("is UTF-16 text", "holds a NUL
// byte ..."), or "" when nothing is. `text` is a whole file or one line; the
// caller says where its first NUL byte is.
std::string text_encoding_problem(std::string_view text);

// What is wrong with the line ends of `line` (one line as std::getline reads
// it, up to an LF), or "" when nothing is: a carriage return with more text
// after it ends no CRLF line, so the file's lines end in CR alone (classic
// Mac OS, some data loggers) and the whole file reads as one line.
std::string line_ending_problem(std::string_view line);

}  // namespace rover::io
