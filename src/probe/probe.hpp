// SPDX-License-Identifier: MIT
/// @file
/// pce-probe: the request loop. Reads JSON Lines, answers each non-blank line with one
/// JSON object on its own line, in order, and keeps going after bad lines.
#pragma once

#include <iosfwd>
#include <optional>
#include <string>

namespace pce_probe {

/// True for a line that holds only JSON whitespace (space, tab, CR, LF): skipped.
bool is_blank(const std::string& line);

/// The response line (without newline) for one input line; `std::nullopt` for a blank
/// line. Never throws.
std::optional<std::string> answer_line(const std::string& line);

/// Answers every line of `in` on `out`, flushing after each response. Returns the exit
/// code: 0 when every line was answered, 1 if writing to `out` failed.
int run(std::istream& in, std::ostream& out);

}  // namespace pce_probe
