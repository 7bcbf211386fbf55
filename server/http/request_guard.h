#pragma once
// The checks every request passes before routing (the server's pre-routing handler):
// - exactly one well-formed Host header (400), naming this server's port if it names one (403), and
//   loopback when the server listens on loopback (DNS rebinding: 403);
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

/// A Host header's parts: a name (a bracketed IPv6 address keeps its brackets) and a port (0: none).
struct HostHeader {
  std::string name;
  int port = 0;
};
/// HOST or HOST:PORT, where HOST is letters, digits, '.' and '-', or [IPv6]; nothing else (no
/// user info, nothing after the brackets, a port of 1..65535).
std::optional<HostHeader> parseHost(const std::string& header);

/// Why `req` must be refused before routing, or nothing. Every request has one well-formed Host
/// (parseHost); a port in it must be `port` (the server's; 0: not checked). `loopback_only`: the
/// Host must name loopback too.
std::optional<Refusal> refusalBeforeRouting(const httplib::Request& req, bool loopback_only, int port);

}  // namespace dash::http
