// SPDX-License-Identifier: MIT
// pce-probe: evaluate single collision pairs from JSON Lines on stdin (docs/probe.md).
#include "probe.hpp"

#include <cstdio>
#include <iostream>
#include <string>

namespace {

constexpr const char* usage_text =
    "Usage: pce-probe [--help]\n"
    "\n"
    "Evaluates single collision pairs with the pce library. Reads JSON Lines on stdin\n"
    "(one request object per line; blank lines are skipped) and writes one JSON object\n"
    "per line on stdout, in the same order.\n"
    "\n"
    "Request fields:\n"
    "  pair        \"vertex_face\" (x = p,t0,t1,t2) | \"edge_edge\" (x = ea0,ea1,eb0,eb1)\n"
    "              | \"point_edge\" (x = p,e0,e1; unsigned only)\n"
    "              | \"point_point\" (x = p,q; unsigned only)\n"
    "  length      \"signed\" | \"unsigned\"\n"
    "  penalty     {\"type\":\"quadratic\",\"stiffness\":k,\"eps\":e}\n"
    "              {\"type\":\"cubic\",\"stiffness\":k,\"eps\":e,\"delta\":d}\n"
    "              {\"type\":\"log_barrier\",\"stiffness\":k,\"dhat\":h}\n"
    "  x           12 numbers (9 for point_edge, 6 for point_point)\n"
    "  side        1 | -1 (optional, default 1; ignored by \"unsigned\")\n"
    "  projection  \"analytic\" (default) | \"numerical\" | \"exact\" | \"gauss_newton\" | \"abs\"\n"
    "              | \"none\"\n"
    "  scalar      \"double\" (default) | \"float\" | \"long_double\"\n"
    "  mollifier   opt-in mollified energy m(X) psi(L), X = |e0 x e1|^2 (optional;\n"
    "              vertex_face and edge_edge only):\n"
    "              {\"threshold\":X} (X > 0, length^4) or\n"
    "              {\"rest\":[12 numbers],\"factor\":f} (X = f |e0|^2 |e1|^2 at rest, f = 1e-3)\n"
    "  closest_feature  true | false (optional, default false; vertex_face and edge_edge,\n"
    "              unsigned, no mollifier): evaluate the kind of the closest features\n"
    "  id          any JSON value, echoed in the response (optional)\n"
    "\n"
    "Response: {\"status\":\"ok\",...,\"length\",\"value\",\"gradient\",\"hessian\",\n"
    "\"projected_hessian\",\"eigenvalues\"} or {\"status\":reason,\"message\":text}.\n"
    "gradient: one entry per coordinate of x; Hessians: its square, row-major;\n"
    "eigenvalues: frame space, 9 (plane kinds), 6 (point_edge) or 3 (point_point).\n"
    "closest_feature requests add \"feature\" (point_plane, line_line, point_edge or\n"
    "point_point) and keep all 12 coordinates.\n"
    "Mollified requests add \"mollified\":true, \"mollifier\" (m) and \"mollifier_threshold\";\n"
    "at X = 0 they give status ok with zeros, m = 0 and no \"length\".\n"
    "\n"
    "Exit status: 0 when every line was answered (even with errors), 1 if stdout could\n"
    "not be written, 2 on usage errors.\n";

bool is_help(const std::string& arg) { return arg == "--help" || arg == "-h"; }

}  // namespace

int main(int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    if (!is_help(argv[i])) {
      std::fprintf(stderr, "pce-probe: unknown argument '%s'\n\n%s", argv[i], usage_text);
      return 2;
    }
  }
  if (argc > 1) {
    std::fputs(usage_text, stdout);
    return 0;
  }
  std::ios::sync_with_stdio(false);
  return pce_probe::run(std::cin, std::cout);
}
