#pragma once
// A string as a JSON string literal, quotes included: the CLI's JSON output and the viewer's page
// messages quote names and messages that may hold anything (camera ids, label names, errors).
#include <string>
#include <string_view>

namespace semfuse {

// Escapes the quote, the backslash and every control character (\n and \t by name, the others as
// \u00XX); bytes from 0x80 pass through, so UTF-8 stays UTF-8.
std::string jsonString(std::string_view text);

}  // namespace semfuse
