#pragma once
// The checks every request passes before routing (the server's pre-routing handler):
// - Host names loopback when the server listens on loopback (DNS rebinding: 403);
// - the path and the query parameters are valid UTF-8 (400: they end up in SQL and JSON);
// - a request that is not GET/HEAD/OPTIONS comes from this server's own pages: an Origin header, when
//   present, names the Host the request was sent to, and Sec-Fetch-Site, when present, is
//   "same-origin" or "none" (403). A page on another site can still send a form POST or a
//   no-cors fetch to 127.0.0.1; the browser marks those with both headers. Tools (curl, the
//   tests) send neither and are let through, as the token checks still apply to them.
#include <optional>
#include <string>
#include <string_view>

namespace httplib {
struct Request;
}

namespace dash::http {

struct Refusal {
  int status = 400;
  std::string message;
};

/// True when `text` is well-formed UTF-8 (no overlong forms, no surrogates, nothing past U+10FFFF).
bool isValidUtf8(std::string_view text);

bool isLoopbackName(const std::string& host);
/// The host name of a Host header, without the port ("[::1]" keeps its brackets).
std::string hostName(const std::string& header);

/// Why `req` must be refused before routing, or nothing. `loopback_only`: the Host check applies.
std::optional<Refusal> refusalBeforeRouting(const httplib::Request& req, bool loopback_only);

}  // namespace dash::http
