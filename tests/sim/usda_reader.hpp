// SPDX-License-Identifier: MIT
// The USD cache tests' reader (test_output.cpp, test_pce_sim.cpp): a small parser of text USD
// (.usda) for the constructs pce::sim's cache uses — layer metadata, nested `def` prims with
// metadata, attributes (`uniform`, a type, a name, a value or `.timeSamples`, metadata) and
// values (numbers, strings, words, tuples, lists). It is not a USD implementation: it reads
// what the writer is meant to write and throws std::runtime_error, with the line, on
// anything else, so a test fails on text a USD reader might not accept.
#pragma once

#include <cctype>
#include <cstdlib>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace pce::sim::usda {

/// A value: a number, a string ("..."), a word (true, "Z" is a string), a tuple (…) or a list […].
struct Value {
  enum Kind { number, string, word, tuple, list } kind = number;
  double x = 0;              ///< number
  std::string text;          ///< string, word, and the number as written
  std::vector<Value> items;  ///< tuple, list
};

struct Attribute {
  std::string type;  ///< e.g. "point3f[]"
  bool uniform = false;
  bool has_value = false;
  Value value;                            ///< the default value, if has_value
  std::map<double, Value> samples;        ///< time samples (`name.timeSamples`)
  std::map<std::string, Value> metadata;  ///< e.g. interpolation
};

struct Prim {
  std::string type, name, path;
  std::map<std::string, Value> metadata;
  std::map<std::string, Attribute> attributes;
  std::vector<std::unique_ptr<Prim>> children;

  const Prim* child(const std::string& n) const {
    for (const auto& c : children)
      if (c->name == n) return c.get();
    return nullptr;
  }
};

struct Layer {
  std::map<std::string, Value> metadata;
  Prim root;  ///< the pseudo-root: the layer's top prims are its children

  /// The prim at an absolute path ("/World/cloth"), or null.
  const Prim* at(const std::string& path) const {
    const Prim* p = &root;
    std::stringstream parts(path.substr(1));
    for (std::string part; p && std::getline(parts, part, '/');) p = p->child(part);
    return p;
  }
};

class Parser {
 public:
  explicit Parser(std::string text) : s_(std::move(text)) {}

  Layer layer() {
    if (s_.rfind("#usda 1.0\n", 0) != 0) fail("no #usda 1.0 header");
    at_ = s_.find('\n') + 1;
    Layer l;
    l.root.path = "";
    if (peek() == "(") l.metadata = metadata();
    while (peek() == "def") prim(l.root);
    if (!peek().empty()) fail("unexpected '" + peek() + "' at the top level");
    return l;
  }

 private:
  [[noreturn]] void fail(const std::string& what) const {
    throw std::runtime_error("usda line " + std::to_string(line()) + ": " + what);
  }
  int line() const {
    int n = 1;
    for (std::size_t i = 0; i < at_ && i < s_.size(); ++i) n += s_[i] == '\n';
    return n;
  }
  void skip() {
    while (at_ < s_.size()) {
      if (std::isspace(static_cast<unsigned char>(s_[at_]))) {
        ++at_;
      } else if (s_[at_] == '#') {
        while (at_ < s_.size() && s_[at_] != '\n') ++at_;
      } else {
        break;
      }
    }
  }
  /// The next token without taking it: punctuation, a "string", or a word/number.
  std::string peek() {
    skip();
    if (at_ >= s_.size()) return "";
    const char c = s_[at_];
    if (std::string("(){}[],:=").find(c) != std::string::npos) return std::string(1, c);
    if (c == '"') {
      const std::size_t end = s_.find('"', at_ + 1);
      if (end == std::string::npos) fail("unterminated string");
      return s_.substr(at_, end - at_ + 1);
    }
    std::size_t end = at_;
    if (s_[end] == '-' || s_[end] == '+') ++end;
    // Letters, digits, '_', '.', an exponent's sign, and ':' inside a name (primvars:displayColor;
    // not the ':' after a time code).
    const auto inside = [&](std::size_t i) {
      const char c = s_[i];
      if (std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '.') return true;
      if ((c == '-' || c == '+') && (s_[i - 1] == 'e' || s_[i - 1] == 'E')) return true;
      return c == ':' && i + 1 < s_.size() && (std::isalpha(static_cast<unsigned char>(s_[i + 1])) || s_[i + 1] == '_');
    };
    while (end < s_.size() && inside(end)) ++end;
    // A type name may end in "[]" (point3f[]).
    if (end + 1 < s_.size() && s_[end] == '[' && s_[end + 1] == ']') end += 2;
    if (end == at_) fail(std::string("unexpected character '") + c + "'");
    return s_.substr(at_, end - at_);
  }
  std::string take() {
    const std::string t = peek();
    if (t.empty()) fail("unexpected end");
    at_ += t.size();
    return t;
  }
  void expect(const std::string& t) {
    const std::string got = take();
    if (got != t) fail("expected '" + t + "', got '" + got + "'");
  }
  static std::string unquote(const std::string& t) { return t.substr(1, t.size() - 2); }

  Value value() {
    const std::string t = peek();
    Value v;
    if (t == "(" || t == "[") {
      take();
      const std::string close = t == "(" ? ")" : "]";
      v.kind = t == "(" ? Value::tuple : Value::list;
      while (peek() != close) {
        v.items.push_back(value());
        if (peek() == ",")
          take();
        else if (peek() != close)
          fail("expected ',' or '" + close + "'");
      }
      take();
      return v;
    }
    take();
    if (t[0] == '"') {
      v.kind = Value::string;
      v.text = unquote(t);
      return v;
    }
    char* end = nullptr;
    v.x = std::strtod(t.c_str(), &end);
    v.text = t;
    v.kind = end == t.c_str() + t.size() ? Value::number : Value::word;
    return v;
  }

  std::map<std::string, Value> metadata() {
    expect("(");
    std::map<std::string, Value> m;
    while (peek() != ")") {
      const std::string key = take();
      expect("=");
      m[key] = value();
    }
    take();
    return m;
  }

  void prim(Prim& parent) {
    expect("def");
    auto p = std::make_unique<Prim>();
    if (peek()[0] != '"') p->type = take();
    const std::string name = take();
    if (name[0] != '"') fail("expected a prim name in quotes");
    p->name = unquote(name);
    p->path = parent.path + "/" + p->name;
    if (peek() == "(") p->metadata = metadata();
    expect("{");
    while (peek() != "}") {
      if (peek() == "def") {
        prim(*p);
        continue;
      }
      Attribute a;
      if (peek() == "uniform") a.uniform = true, take();
      a.type = take();
      std::string attribute = take();
      const std::string suffix = ".timeSamples";
      const bool sampled = attribute.size() > suffix.size() &&
                           attribute.compare(attribute.size() - suffix.size(), suffix.size(), suffix) == 0;
      if (sampled) attribute.resize(attribute.size() - suffix.size());
      Attribute& stored = p->attributes[attribute];
      if (!stored.type.empty() && stored.type != a.type) fail("attribute " + attribute + " declared twice");
      stored.type = a.type, stored.uniform = a.uniform;
      if (peek() == "=") {
        take();
        if (sampled) {
          expect("{");
          while (peek() != "}") {
            const Value time = value();
            if (time.kind != Value::number) fail("a time code must be a number");
            expect(":");
            stored.samples[time.x] = value();
            if (peek() == ",")
              take();
            else if (peek() != "}")
              fail("expected ',' or '}' in time samples");
          }
          take();
        } else {
          stored.value = value();
          stored.has_value = true;
        }
      }
      if (peek() == "(") stored.metadata = metadata();
    }
    take();
    parent.children.push_back(std::move(p));
  }

  std::string s_;
  std::size_t at_ = 0;
};

/// Parses the file at `path`.
inline Layer read(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(path + ": cannot open");
  std::stringstream s;
  s << in.rdbuf();
  return Parser(s.str()).layer();
}

/// A list of (x, y, z) tuples as float columns.
inline std::vector<float> floats(const Value& list) {
  std::vector<float> out;
  for (const Value& t : list.items)
    for (const Value& c : t.items) out.push_back(static_cast<float>(c.x));
  return out;
}

/// A list of integers.
inline std::vector<int> ints(const Value& list) {
  std::vector<int> out;
  for (const Value& v : list.items) out.push_back(static_cast<int>(v.x));
  return out;
}

}  // namespace pce::sim::usda
