// SPDX-License-Identifier: MIT
// The saved state of self contact (saved_state.hpp).
#include "saved_state.hpp"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <stdexcept>

namespace pce::sim::contact {

std::string encode(const SavedContact& s) {
  std::string out;
  const std::uint64_t count = s.pairs.size();
  out.append(reinterpret_cast<const char*>(&count), sizeof count);
  for (std::size_t k = 0; k < s.pairs.size(); ++k) {
    const std::int32_t ab[2] = {s.pairs[k][0], s.pairs[k][1]};
    const signed char flags[2] = {s.sides[k], static_cast<signed char>(s.declared[k])};
    out.append(reinterpret_cast<const char*>(ab), sizeof ab);
    out.append(reinterpret_cast<const char*>(flags), sizeof flags);
  }
  if (s.with_query) {
    const char head[2] = {1, static_cast<char>(s.validity_bound ? 1 : 0)};
    out.append(head, sizeof head);
    out.append(reinterpret_cast<const char*>(s.at.data()), sizeof(double) * static_cast<std::size_t>(s.at.size()));
    out.append(reinterpret_cast<const char*>(s.to.data()), sizeof(double) * static_cast<std::size_t>(s.to.size()));
  }
  if (!s.stiffening.empty()) {
    out.push_back(2);
    out.append(reinterpret_cast<const char*>(s.stiffening.data()), sizeof(double) * s.stiffening.size());
  }
  return out;
}

namespace {

/// Reads the query part at `q` (2 + 2 × 3n bytes) into `s`.
void decode_query(const char* q, const std::string& name, std::size_t n, SavedContact& s) {
  if (q[0] != 1 || (q[1] != 0 && q[1] != 1))
    throw std::invalid_argument(name + ": the saved query's header is not 1 followed by 0 or 1");
  s.at.resize(3, static_cast<Eigen::Index>(n));
  s.to.resize(3, static_cast<Eigen::Index>(n));
  std::memcpy(s.at.data(), q + 2, sizeof(double) * 3 * n);
  std::memcpy(s.to.data(), q + 2 + sizeof(double) * 3 * n, sizeof(double) * 3 * n);
  if (!s.at.allFinite() || !s.to.allFinite())
    throw std::invalid_argument(name + ": the saved query's positions are not all finite");
  s.with_query = true;
  s.validity_bound = q[1] == 1;
}

}  // namespace

SavedContact decode(const std::string& state, const char* effect, long vertices, long first_max, long second_max) {
  const std::string name(effect);
  constexpr std::size_t record = 2 * sizeof(std::int32_t) + 2;
  std::uint64_t count = 0;
  if (state.size() < sizeof count) throw std::invalid_argument(name + ": truncated state");
  std::memcpy(&count, state.data(), sizeof count);
  const auto n = static_cast<std::size_t>(vertices);
  const std::size_t query_part = 2 + 2 * 3 * n * sizeof(double);
  if (count > (state.size() - sizeof count) / record)
    throw std::invalid_argument(name + ": the state's size does not match its pair count");
  const std::size_t pairs_end = sizeof count + count * record;
  // The parts after the pairs: the query's (even size) and the factors' (odd size).
  const std::size_t factors_part = 1 + count * sizeof(double);
  const std::size_t rest = state.size() - pairs_end;
  const bool with_query = n > 0 && (rest == query_part || rest == query_part + factors_part);
  const bool with_factors = rest == factors_part || (with_query && rest == query_part + factors_part);
  if (rest != 0 && !with_query && !with_factors)
    throw std::invalid_argument(name + ": the state's size does not match its pair count");
  SavedContact s;
  s.pairs.resize(count);
  s.sides.resize(count);
  s.declared.resize(count);
  const char* p = state.data() + sizeof count;
  for (std::size_t k = 0; k < count; ++k, p += record) {
    std::int32_t ab[2];
    signed char flags[2];
    std::memcpy(ab, p, sizeof ab);
    std::memcpy(flags, p + sizeof ab, sizeof flags);
    if (ab[0] < 0 || ab[0] >= first_max || ab[1] < 0 || ab[1] >= second_max || flags[0] < -1 || flags[0] > 1 ||
        flags[1] < 0 || flags[1] > 1 || (k > 0 && !(s.pairs[k - 1] < std::array<int, 2>{ab[0], ab[1]})))
      throw std::invalid_argument(name + ": pair " + std::to_string(k) + " of the saved state does not fit this model");
    s.pairs[k] = {ab[0], ab[1]};
    s.sides[k] = flags[0];
    s.declared[k] = flags[1];
  }
  if (with_query) decode_query(state.data() + pairs_end, name, n, s);
  if (with_factors) {
    const char* f = state.data() + pairs_end + (with_query ? query_part : 0);
    if (f[0] != 2) throw std::invalid_argument(name + ": the saved stiffening factors' header is not 2");
    s.stiffening.resize(count);
    std::memcpy(s.stiffening.data(), f + 1, sizeof(double) * count);
    for (const double m : s.stiffening)
      if (!(m >= 1 && std::isfinite(m)))
        throw std::invalid_argument(name + ": a saved stiffening factor is not a finite number >= 1");
  }
  return s;
}

}  // namespace pce::sim::contact
