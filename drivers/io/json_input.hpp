#pragma once

// JSON from outside the process (a client's message, a request body, a file) is parsed through here, with
// a bound on its nesting. nlohmann's parser itself keeps its own stack, but dump(), comparisons, copies and
// our own walks over a document recurse once per level: a body of 70,000 nested arrays overflows the stack
// there. No message or file of ours nests deeper than a handful of levels.

#include <cstddef>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

namespace strata::io {

/// Deeper than this is refused. Strata's own documents nest at most 5 levels.
inline constexpr std::size_t kMaxJsonDepth = 64;

/// A parsed document, or why there is none.
struct JsonInput {
  nlohmann::json value;  ///< null when `error` is set
  std::string error;     ///< empty when parsed; otherwise for people ("nested deeper than 64 levels")
  [[nodiscard]] bool ok() const { return error.empty(); }
};

namespace detail {

/// Counts nesting and stops the parse (returns false) at the first level beyond the bound.
class DepthBound : public nlohmann::json_sax<nlohmann::json> {
 public:
  explicit DepthBound(std::size_t max_depth) : max_depth_(max_depth) {}
  bool null() override { return true; }
  bool boolean(bool /*value*/) override { return true; }
  bool number_integer(number_integer_t /*value*/) override { return true; }
  bool number_unsigned(number_unsigned_t /*value*/) override { return true; }
  bool number_float(number_float_t /*value*/, const string_t& /*text*/) override { return true; }
  bool string(string_t& /*value*/) override { return true; }
  bool binary(binary_t& /*value*/) override { return true; }
  bool start_object(std::size_t /*elements*/) override { return enter(); }
  bool key(string_t& /*value*/) override { return true; }
  bool end_object() override { return leave(); }
  bool start_array(std::size_t /*elements*/) override { return enter(); }
  bool end_array() override { return leave(); }
  bool parse_error(std::size_t position, const std::string& /*token*/,
                   const nlohmann::detail::exception& /*error*/) override {
    error_position_ = position;  // not the token: it would echo the input back
    return false;
  }
  [[nodiscard]] bool too_deep() const { return too_deep_; }
  [[nodiscard]] std::size_t error_position() const { return error_position_; }

 private:
  bool enter() {
    too_deep_ = ++depth_ > max_depth_;
    return !too_deep_;
  }
  bool leave() {
    --depth_;
    return true;
  }
  std::size_t max_depth_;
  std::size_t depth_ = 0;
  bool too_deep_ = false;
  std::size_t error_position_ = 0;
};

}  // namespace detail

/// Parses `text` as one JSON document nested at most `max_depth` levels (an array or object is a level).
[[nodiscard]] inline JsonInput parse_json(std::string_view text, std::size_t max_depth = kMaxJsonDepth) {
  JsonInput input;
  detail::DepthBound bound(max_depth);
  // The first pass builds nothing and stops at the first level too deep; only a bounded document is built.
  if (!nlohmann::json::sax_parse(text, &bound)) {
    input.error = bound.too_deep()
                      ? "nested deeper than " + std::to_string(max_depth) + " levels"
                      : "not valid JSON (at byte " + std::to_string(bound.error_position()) + ")";
    return input;
  }
  input.value = nlohmann::json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (input.value.is_discarded()) {
    input.value = nullptr;
    input.error = "not valid JSON";
  }
  return input;
}

}  // namespace strata::io
