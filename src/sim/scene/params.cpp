// SPDX-License-Identifier: MIT
#include "params.hpp"

#include "../util/names.hpp"

#include <cmath>
#include <sstream>

namespace pce::sim {

namespace {
const char* type_name(const nlohmann::json& j) {
  if (j.is_null()) return "null";
  if (j.is_boolean()) return "a boolean";
  if (j.is_number()) return "a number";
  if (j.is_string()) return "a string";
  if (j.is_array()) return "an array";
  return "an object";
}
std::string number_text(double v) {
  std::ostringstream s;
  s.precision(17);
  s << v;
  return s.str();
}
}  // namespace

Params::Params(const nlohmann::json& object, std::string file, std::string path)
    : j_(&object), file_(std::move(file)), path_(std::move(path)) {
  if (!object.is_object())
    throw InputError(file_, path_.empty() ? "(root)" : path_,
                     std::string("expected an object, got ") + type_name(object));
}

bool Params::has(const std::string& key) const { return j_->contains(key); }

std::string Params::path_of(const std::string& key) const { return path_.empty() ? key : path_ + "." + key; }

std::string Params::join(const std::string& field) const {
  if (field.empty()) return path_;
  if (field.front() == '[') return path_ + field;
  return path_of(field);
}

void Params::fail(const std::string& key, const std::string& what) const {
  throw InputError(file_, path_of(key), what);
}

const nlohmann::json& Params::at(const std::string& key) const {
  const auto it = j_->find(key);
  if (it == j_->end()) fail(key, "missing required field");
  return *it;
}

double Params::number(const std::string& key, std::optional<double> fallback, double lo, double hi) const {
  if (!has(key)) {
    if (fallback) return *fallback;
    fail(key, "missing required field (a number)");
  }
  const nlohmann::json& j = at(key);
  if (!j.is_number()) fail(key, std::string("expected a number, got ") + type_name(j));
  const double v = j.get<double>();
  if (!std::isfinite(v)) fail(key, "expected a finite number");
  if (v < lo || v > hi)
    fail(key, "expected a number in [" + number_text(lo) + ", " + number_text(hi) + "], got " + number_text(v));
  return v;
}

double Params::positive(const std::string& key, std::optional<double> fallback) const {
  const double v = number(key, fallback);
  if (!(v > 0)) fail(key, "expected a number > 0, got " + number_text(v));
  return v;
}

double Params::nonnegative(const std::string& key, std::optional<double> fallback) const {
  const double v = number(key, fallback);
  if (!(v >= 0)) fail(key, "expected a number >= 0, got " + number_text(v));
  return v;
}

long Params::integer(const std::string& key, std::optional<long> fallback, long lo, long hi) const {
  if (!has(key)) {
    if (fallback) return *fallback;
    fail(key, "missing required field (an integer)");
  }
  const nlohmann::json& j = at(key);
  if (!j.is_number_integer() &&
      !(j.is_number_float() && std::floor(j.get<double>()) == j.get<double>() && std::abs(j.get<double>()) < 1e15))
    fail(key, std::string("expected an integer, got ") + type_name(j));
  const long v = j.is_number_integer() ? j.get<long>() : static_cast<long>(j.get<double>());
  if (v < lo || v > hi)
    fail(key,
         "expected an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got " + std::to_string(v));
  return v;
}

bool Params::boolean(const std::string& key, std::optional<bool> fallback) const {
  if (!has(key)) {
    if (fallback) return *fallback;
    fail(key, "missing required field (true or false)");
  }
  const nlohmann::json& j = at(key);
  if (!j.is_boolean()) fail(key, std::string("expected true or false, got ") + type_name(j));
  return j.get<bool>();
}

std::string Params::string(const std::string& key, std::optional<std::string> fallback) const {
  if (!has(key)) {
    if (fallback) return *fallback;
    fail(key, "missing required field (a string)");
  }
  const nlohmann::json& j = at(key);
  if (!j.is_string()) fail(key, std::string("expected a string, got ") + type_name(j));
  return j.get<std::string>();
}

Eigen::Vector3d Params::vec3(const std::string& key, std::optional<Eigen::Vector3d> fallback) const {
  if (!has(key)) {
    if (fallback) return *fallback;
    fail(key, "missing required field (an array of 3 numbers)");
  }
  const nlohmann::json& j = at(key);
  if (!j.is_array() || j.size() != 3) fail(key, "expected an array of 3 numbers");
  Eigen::Vector3d v;
  for (int k = 0; k < 3; ++k) {
    if (!j[static_cast<std::size_t>(k)].is_number()) fail(key, "expected an array of 3 numbers");
    v[k] = j[static_cast<std::size_t>(k)].get<double>();
    if (!std::isfinite(v[k])) fail(key, "expected finite numbers");
  }
  return v;
}

std::vector<int> Params::indices(const std::string& key, long hi) const {
  const nlohmann::json& j = at(key);
  if (!j.is_array()) fail(key, std::string("expected an array of vertex indices, got ") + type_name(j));
  std::vector<int> out;
  out.reserve(j.size());
  for (std::size_t k = 0; k < j.size(); ++k) {
    const nlohmann::json& e = j[k];
    if (!e.is_number_integer())
      throw InputError(file_, path_of(key) + "[" + std::to_string(k) + "]", "expected an integer");
    const long v = e.get<long>();
    if (v < 0 || v >= hi)
      throw InputError(file_, path_of(key) + "[" + std::to_string(k) + "]",
                       "index " + std::to_string(v) + " out of range [0, " + std::to_string(hi) + ")");
    out.push_back(static_cast<int>(v));
  }
  return out;
}

Params Params::object(const std::string& key) const { return Params(at(key), file_, path_of(key)); }

const nlohmann::json& Params::array(const std::string& key, bool required) const {
  static const nlohmann::json empty = nlohmann::json::array();
  if (!has(key)) {
    if (required) fail(key, "missing required field (an array)");
    return empty;
  }
  const nlohmann::json& j = at(key);
  if (!j.is_array()) fail(key, std::string("expected an array, got ") + type_name(j));
  return j;
}

Params Params::element(const std::string& key, std::size_t i) const {
  return Params(array(key, true).at(i), file_, path_of(key) + "[" + std::to_string(i) + "]");
}

void Params::only(std::initializer_list<const char*> known) const {
  for (auto it = j_->begin(); it != j_->end(); ++it) {
    bool ok = false;
    for (const char* k : known) ok = ok || it.key() == k;
    if (!ok) fail(it.key(), "unknown field (expected one of: " + join_names(known, "") + ")");
  }
}

}  // namespace pce::sim
