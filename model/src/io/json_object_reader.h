#pragma once
// Strict reading of JSON config objects (network configs, training configs): every value is
// type-checked, errors name the source, the field path and the value, and keys that were never
// read (typos) are errors at finish(). Required fields are read with the value-returning
// methods; optional ones with the read*() methods, which leave the default in place when the
// key is absent.
#include "io/json_text.h"
#include "simpli/error.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdint>
#include <limits>
#include <set>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace simpli::io {

class JsonObjectReader {
public:
  using json = nlohmann::json;

  JsonObjectReader(const json& object, std::string source, std::string path)
      : object_(object), source_(std::move(source)), path_(std::move(path)) {
    if (!object_.is_object())
      fail(source_, ": ", where(""), " is ", jsonExcerpt(object_), ", expected a JSON object");
  }

  /// "field \"a.b\"" for key b under path a; "the top level" for the root itself.
  std::string where(const std::string& key) const {
    if (key.empty())
      return path_.empty() ? "the top level" : "field \"" + path_ + "\"";
    return "field \"" + childPath(key) + "\"";
  }
  std::string childPath(const std::string& key) const {
    return path_.empty() ? key : path_ + "." + key;
  }
  const std::string& source() const { return source_; }
  bool has(const std::string& key) const { return object_.contains(key); }

  /// The value of an optional key (marked as read), or null when absent.
  const json* find(const std::string& key) {
    auto it = object_.find(key);
    if (it == object_.end())
      return nullptr;
    used_.insert(key);
    return &*it;
  }
  const json& require(const std::string& key) {
    const json* v = find(key);
    if (!v)
      fail(source_, ": missing ", where(key));
    return *v;
  }

  // ---- required values -------------------------------------------------------------------
  int integer(const std::string& key, int lo, int hi) {
    return integerValue(require(key), where(key), lo, hi);
  }
  int integerValue(const json& v, const std::string& what, int lo, int hi) const {
    const int64_t i = checkedInteger(v, what);
    if (i < lo || i > hi)
      fail(source_, ": ", what, " = ", i, " is outside [", lo, ", ", hi, "]");
    return static_cast<int>(i);
  }
  double number(const std::string& key) { return numberValue(require(key), where(key)); }
  bool boolean(const std::string& key) {
    const json& v = require(key);
    if (!v.is_boolean())
      fail(source_, ": ", where(key), " is ", jsonExcerpt(v), ", expected true or false");
    return v.get<bool>();
  }
  std::string string(const std::string& key) {
    const json& v = require(key);
    if (!v.is_string())
      fail(source_, ": ", where(key), " is ", jsonExcerpt(v), ", expected a string");
    return v.get<std::string>();
  }
  std::vector<int> integers(const std::string& key, int minCount, int maxCount) {
    const json& v = require(key);
    if (!v.is_array() || static_cast<int>(v.size()) < minCount ||
        static_cast<int>(v.size()) > maxCount)
      fail(source_, ": ", where(key), " is ", jsonExcerpt(v), ", expected an array of ", minCount,
           minCount == maxCount ? "" : " to " + std::to_string(maxCount), " positive integers");
    std::vector<int> out;
    for (std::size_t i = 0; i < v.size(); ++i)
      out.push_back(integerValue(v[i], where(key + "[" + std::to_string(i) + "]"), 1, 1 << 20));
    return out;
  }
  JsonObjectReader object(const std::string& key) {
    return JsonObjectReader(require(key), source_, childPath(key));
  }

  // ---- optional values (the default stays when the key is absent) --------------------------
  void readNumber(const std::string& key, double& out) {
    if (const json* v = find(key))
      out = numberValue(*v, where(key));
  }
  template <typename Int> void readInteger(const std::string& key, Int& out) {
    if (const json* v = find(key))
      out = integerOfType<Int>(*v, where(key));
  }
  /// [integer, integer]; each must fit Int (a cast would wrap 2^32 + 1 to 1 silently).
  template <typename Int> void readIntegerPair(const std::string& key, Int& a, Int& b) {
    if (const json* v = find(key)) {
      if (!v->is_array() || v->size() != 2)
        fail(source_, ": ", where(key), " is ", jsonExcerpt(*v), ", expected [integer, integer]");
      a = integerOfType<Int>((*v)[0], where(key + "[0]"));
      b = integerOfType<Int>((*v)[1], where(key + "[1]"));
    }
  }
  void readPair(const std::string& key, double& a, double& b) {
    if (const json* v = find(key)) {
      if (!v->is_array() || v->size() != 2 || !(*v)[0].is_number() || !(*v)[1].is_number())
        fail(source_, ": ", where(key), " is ", jsonExcerpt(*v), ", expected [number, number]");
      a = (*v)[0].get<double>();
      b = (*v)[1].get<double>();
    }
  }
  void readNumbers(const std::string& key, std::vector<double>& out) {
    if (const json* v = find(key)) {
      bool ok = v->is_array() && !v->empty();
      for (std::size_t i = 0; ok && i < v->size(); ++i)
        ok = (*v)[i].is_number() && std::isfinite((*v)[i].get<double>());
      if (!ok)
        fail(source_, ": ", where(key), " is ", jsonExcerpt(*v),
             ", expected a non-empty list of finite numbers");
      out = v->get<std::vector<double>>();
    }
  }

  /// Throws for keys that were never read.
  void finish() const {
    for (auto it = object_.begin(); it != object_.end(); ++it)
      if (!used_.count(it.key()))
        fail(source_, ": unknown ", where(it.key()));
  }

private:
  int64_t checkedInteger(const json& v, const std::string& what) const {
    if (!v.is_number_integer())
      fail(source_, ": ", what, " is ", jsonExcerpt(v), ", expected an integer");
    if (v.is_number_unsigned() && v.get<uint64_t>() > uint64_t(std::numeric_limits<int64_t>::max()))
      fail(source_, ": ", what, " = ", v.get<uint64_t>(), " is too large");
    return v.get<int64_t>();
  }
  template <typename Int> Int integerOfType(const json& v, const std::string& what) const {
    static_assert(std::is_signed_v<Int>, "for unsigned fields, check the sign first");
    const int64_t i = checkedInteger(v, what);
    if (i < int64_t(std::numeric_limits<Int>::min()) ||
        i > int64_t(std::numeric_limits<Int>::max()))
      fail(source_, ": ", what, " = ", i, " is outside [", std::numeric_limits<Int>::min(), ", ",
           std::numeric_limits<Int>::max(), "]");
    return static_cast<Int>(i);
  }
  double numberValue(const json& v, const std::string& what) const {
    if (!v.is_number())
      fail(source_, ": ", what, " is ", jsonExcerpt(v), ", expected a number");
    const double d = v.get<double>();
    if (!std::isfinite(d))
      fail(source_, ": ", what, " = ", d, " is not finite");
    return d;
  }

  const json& object_;
  std::string source_, path_;
  std::set<std::string> used_;
};

} // namespace simpli::io
