// SPDX-License-Identifier: MIT
// pce-probe: one line in, one line out (parse -> evaluate -> format), and the loop over stdin.
#include "probe.hpp"

#include "evaluate.hpp"
#include "request.hpp"
#include "response.hpp"

#include <exception>
#include <istream>
#include <ostream>
#include <utility>

namespace pce_probe {

namespace {

/// Parses and evaluates one non-blank line; the echoed "id" is attached to every response
/// of a line that parsed as a JSON object.
Response respond(const std::string& line) {
  std::optional<nlohmann::json> id;
  Response r;
  try {
    const nlohmann::json request = parse_json_line(line);
    id = request_id(request);
    r = evaluate_request(parse_request(request));
  } catch (const InvalidRequest& e) {
    r = error_response("invalid_request", e.what());
  } catch (const std::exception& e) {
    r = error_response("internal_error", std::string("unexpected error: ") + e.what());
  }
  r.id = std::move(id);
  return r;
}

}  // namespace

bool is_blank(const std::string& line) { return line.find_first_not_of(" \t\r\n") == std::string::npos; }

std::optional<std::string> answer_line(const std::string& line) {
  if (is_blank(line)) return std::nullopt;
  try {
    return format_response(respond(line));
  } catch (const std::exception&) {
    return std::string(R"({"status":"internal_error","message":"could not format the response"})");
  }
}

int run(std::istream& in, std::ostream& out) {
  std::string line;
  while (std::getline(in, line)) {
    const std::optional<std::string> answer = answer_line(line);
    if (!answer) continue;
    out << *answer << '\n';
    out.flush();
    if (!out) return 1;
  }
  return 0;
}

}  // namespace pce_probe
