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

// The offset of the first byte of `text` that begins no well-formed UTF-8
// character (RFC 3629: no overlong form, no surrogate, nothing beyond
// U+10FFFF), or std::string_view::npos when `text` is UTF-8 throughout.
std::size_t invalid_utf8_offset(std::string_view text);

// Why the bytes at `offset` (invalid_utf8_offset()) are no UTF-8:
// "byte 0xE9 begins a 3-byte character, but the next byte 0x20 does not
// continue it", "byte 0xFF begins no UTF-8 character".
std::string invalid_utf8_description(std::string_view text, std::size_t offset);

}  // namespace rover::io
