// Plain words for a JSON syntax error: the JSON library's report ("syntax
// error while parsing object key - unexpected '}'; expected string literal")
// turned into what a person editing a config did ("a comma before '}': JSON
// allows no comma after an object's last entry").
#pragma once

#include <cstddef>
#include <string>

namespace rover::io {

// `library_reason`: the parser's message after its position prefix; `text`:
// the whole input; `offending`: the byte offset of the character the parser
// stopped at.
std::string json_syntax_problem(const std::string& library_reason, const std::string& text, std::size_t offending);

}  // namespace rover::io
