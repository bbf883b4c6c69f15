#pragma once
// JSON documents read by the model (network and training configs, MLI meta.json, safetensors
// headers, checkpoint state): one parser with a nesting limit, and short value excerpts for
// error messages. nlohmann's parser keeps its own stack, but dump() and comparisons recurse
// once per level, so a document of 100000 '[' would overflow the stack in the first message
// that quotes it; no simpli document nests deeper than a few levels.
#include "simpli/error.h"

#include <nlohmann/json.hpp>

#include <string>

namespace simpli::io {

/// The deepest nesting (arrays and objects) parseJson accepts.
inline constexpr int kMaxJsonDepth = 64;

/// Parses `text`. Throws simpli::Error "<source>: not valid JSON (...)" or "<source>: nested
/// deeper than 64 levels ..." (never nlohmann's own exceptions).
inline nlohmann::json parseJson(const std::string& text, const std::string& source) {
  const auto limitDepth = [&source](int depth, nlohmann::json::parse_event_t event,
                                    nlohmann::json&) {
    if (depth >= kMaxJsonDepth && (event == nlohmann::json::parse_event_t::object_start ||
                                   event == nlohmann::json::parse_event_t::array_start))
      fail(source, ": JSON nested deeper than ", kMaxJsonDepth,
           " levels (arrays and objects); no simpli document does that");
    return true;
  };
  try {
    return nlohmann::json::parse(text, limitDepth);
  } catch (const nlohmann::json::exception& e) {
    fail(source, ": not valid JSON (", e.what(), ")");
  }
}

/// A value for an error message, cut to about 60 characters; never deeper than the excerpt.
inline void appendJsonExcerpt(const nlohmann::json& value, std::string& out, std::size_t budget) {
  if (out.size() > budget)
    return;
  if (value.is_array() || value.is_object()) {
    out += value.is_array() ? '[' : '{';
    bool first = true;
    for (auto it = value.begin(); it != value.end() && out.size() <= budget; ++it) {
      out += first ? "" : ",";
      first = false;
      if (value.is_object())
        out += nlohmann::json(it.key()).dump(-1, ' ', false,
                                             nlohmann::json::error_handler_t::replace) +
               ":";
      appendJsonExcerpt(*it, out, budget);
    }
    if (out.size() <= budget)
      out += value.is_array() ? ']' : '}';
    return;
  }
  out += value.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

inline std::string jsonExcerpt(const nlohmann::json& value) {
  constexpr std::size_t kLength = 60;
  std::string s;
  appendJsonExcerpt(value, s, kLength);
  return s.size() > kLength ? s.substr(0, kLength - 3) + "..." : s;
}

} // namespace simpli::io
