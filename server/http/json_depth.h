#pragma once
// Nesting depth of JSON text, measured on the bytes before any parser sees them. nlohmann-json
// parses iteratively but dump(), comparison and the readers recurse: a body nested 50,000 deep
// overflowed the stack (issue 24). The server refuses bodies deeper than kMaxJsonDepth with 400.
#include <cstddef>
#include <string_view>

namespace dash::http {

/// Far deeper than any request the API defines (a batch spec nests about 5 levels), far shallower
/// than what overflows a worker thread's stack (20,000 levels survived, 50,000 did not).
inline constexpr std::size_t kMaxJsonDepth = 256;

/// The deepest nesting of [ and { outside strings, counting no further than `stop_at` (it returns as
/// soon as that depth is reached, so a hostile body costs one partial scan). Not a validator: text
/// that is not JSON still gets a number, and the parser then refuses it.
std::size_t jsonNestingDepth(std::string_view text, std::size_t stop_at = kMaxJsonDepth + 1);

/// True when `text` nests deeper than kMaxJsonDepth.
bool jsonTooDeep(std::string_view text);

}  // namespace dash::http
