// SPDX-License-Identifier: MIT
// pce-probe: rendering of responses as single-line JSON objects (keys in docs/probe.md).
#include "response.hpp"

#include <cmath>
#include <cstddef>
#include <cstdio>
#include <utility>

namespace pce_probe {

namespace {

/// Appends `"key":value` members to one JSON object.
class ObjectWriter {
 public:
  ObjectWriter() : out_("{") {}

  void raw(const char* key, const std::string& json_text) {
    if (!first_) out_ += ',';
    first_ = false;
    out_ += '"';
    out_ += key;  // keys are fixed identifiers: no escaping needed
    out_ += "\":";
    out_ += json_text;
  }
  void string(const char* key, const std::string& value) { raw(key, escaped(value)); }
  void number(const char* key, double value) { raw(key, format_number(value)); }
  void numbers(const char* key, const std::vector<double>& values) {
    std::string text = "[";
    for (std::size_t i = 0; i < values.size(); ++i) {
      if (i != 0) text += ',';
      text += format_number(values[i]);
    }
    text += ']';
    raw(key, text);
  }
  std::string finish() { return out_ + "}"; }

  static std::string escaped(const nlohmann::json& value) {
    return value.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
  }

 private:
  std::string out_;
  bool first_ = true;
};

void write_evaluation(ObjectWriter& w, const Evaluation& e) {
  w.string("projection", e.projection);
  w.string("scalar", e.scalar);
  if (e.mollifier) {
    w.raw("mollified", "true");
    w.number("mollifier", e.mollifier->value);
    w.number("mollifier_threshold", e.mollifier->threshold);
  }
  if (e.feature) w.string("feature", *e.feature);
  if (e.length) w.number("length", *e.length);
  w.number("value", e.value);
  w.numbers("gradient", e.gradient);
  w.numbers("hessian", e.hessian);
  w.numbers("projected_hessian", e.projected_hessian);
  w.numbers("eigenvalues", e.eigenvalues);
}

}  // namespace

Response error_response(std::string status, std::string message) {
  Response r;
  r.status = std::move(status);
  r.message = std::move(message);
  return r;
}

std::string format_number(double v) {
  if (v == 0.0 && std::signbit(v)) return "-0.0";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

std::string format_response(const Response& r) {
  ObjectWriter w;
  w.string("status", r.status);
  if (r.id) w.raw("id", ObjectWriter::escaped(*r.id));
  if (r.evaluation)
    write_evaluation(w, *r.evaluation);
  else
    w.string("message", r.message);
  return w.finish();
}

}  // namespace pce_probe
