#pragma once
// A tiny JSON emitter for semfuse-query's --json output: enough for objects of numbers, strings
// and arrays, written in order, with no dependency for what is a few dozen lines of text.
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

#include "semfuse/core/json_text.hpp"

namespace semfuse::tools {

// Builds one JSON value by hand: obj.field("a", 1).field("b", "x").
class JsonObject {
 public:
  template <class T>
  JsonObject& field(std::string_view key, const T& value) {
    add(key, toJson(value));
    return *this;
  }
  JsonObject& raw(std::string_view key, const std::string& json) {
    add(key, json);
    return *this;
  }
  std::string str() const { return "{" + body_ + "}"; }

 private:
  static std::string toJson(const std::string& v) { return jsonString(v); }
  static std::string toJson(const char* v) { return jsonString(v); }
  static std::string toJson(bool v) { return v ? "true" : "false"; }
  static std::string toJson(double v);
  template <class T>
  static std::string toJson(const T& v) {
    return std::to_string(v);
  }
  void add(std::string_view key, const std::string& json) {
    if (!body_.empty()) body_ += ", ";
    body_ += jsonString(key) + ": " + json;
  }
  std::string body_;
};

std::string jsonArray(const std::vector<std::string>& items);

}  // namespace semfuse::tools
