#include "server/http/request_guard.h"

#include <algorithm>
#include <cctype>

// clang-format off
#include <httplib.h>  // last: it must follow Eigen (see server/dispatch/dispatch_routes.h)
// clang-format on

namespace dash::http {

namespace {

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

bool changesSomething(const std::string& method) { return method != "GET" && method != "HEAD" && method != "OPTIONS"; }

/// Messages quote what was sent; cut and cleaned so that the answer stays small and valid.
std::string quoted(const std::string& text) {
  constexpr std::size_t kMaxQuoted = 100;
  std::string out;
  for (const char c : text.substr(0, kMaxQuoted)) {
    const auto u = static_cast<unsigned char>(c);
    out += u >= 0x20 && u < 0x7f ? c : '?';
  }
  return out + (text.size() > kMaxQuoted ? "..." : "");
}

}  // namespace

bool isValidUtf8(std::string_view text) {
  std::size_t i = 0;
  const std::size_t n = text.size();
  while (i < n) {
    const auto c = static_cast<unsigned char>(text[i]);
    if (c < 0x80) {
      ++i;
      continue;
    }
    std::size_t length = 0;
    char32_t code = 0;
    char32_t least = 0;
    if ((c & 0xE0) == 0xC0) {
      length = 2, code = c & 0x1F, least = 0x80;
    } else if ((c & 0xF0) == 0xE0) {
      length = 3, code = c & 0x0F, least = 0x800;
    } else if ((c & 0xF8) == 0xF0) {
      length = 4, code = c & 0x07, least = 0x10000;
    } else {
      return false;
    }
    if (i + length > n) return false;
    for (std::size_t k = 1; k < length; ++k) {
      const auto t = static_cast<unsigned char>(text[i + k]);
      if ((t & 0xC0) != 0x80) return false;
      code = (code << 6) | (t & 0x3F);
    }
    if (code < least || code > 0x10FFFF || (code >= 0xD800 && code <= 0xDFFF)) return false;
    i += length;
  }
  return true;
}

bool isLoopbackName(const std::string& host) {
  const std::string h = lower(host);
  return h == "127.0.0.1" || h == "localhost" || h == "::1" || h == "[::1]";
}

std::string hostName(const std::string& header) {
  if (!header.empty() && header[0] == '[') {
    const auto close = header.find(']');
    return close == std::string::npos ? header : header.substr(0, close + 1);
  }
  return header.substr(0, header.find(':'));
}

std::optional<HostHeader> parseHost(const std::string& header) {
  HostHeader out;
  std::size_t end = 0;
  if (!header.empty() && header[0] == '[') {
    end = header.find(']');
    if (end == std::string::npos || end == 1) return std::nullopt;
    for (std::size_t i = 1; i < end; ++i) {
      if (std::isxdigit(static_cast<unsigned char>(header[i])) == 0 && header[i] != ':' && header[i] != '.')
        return std::nullopt;
    }
    ++end;
  } else {
    while (end < header.size() &&
           (std::isalnum(static_cast<unsigned char>(header[end])) != 0 || header[end] == '.' || header[end] == '-'))
      ++end;
    if (end == 0) return std::nullopt;
  }
  out.name = header.substr(0, end);
  if (end == header.size()) return out;
  if (header[end] != ':' || end + 1 == header.size() || header.size() - end - 1 > 5) return std::nullopt;
  int port = 0;
  for (std::size_t i = end + 1; i < header.size(); ++i) {
    if (std::isdigit(static_cast<unsigned char>(header[i])) == 0) return std::nullopt;
    port = port * 10 + (header[i] - '0');
  }
  if (port < 1 || port > 65535) return std::nullopt;
  out.port = port;
  return out;
}

std::optional<Refusal> refusalBeforeRouting(const httplib::Request& req, bool loopback_only, int port) {
  // Exactly one Host, well formed: no Host, two of them (127.0.0.1 then evil.com), 127.0.0.1:PORT@evil.com
  // and [::1]evil.com were all answered (issue 40).
  const std::size_t hosts = req.get_header_value_count("Host");
  if (hosts != 1) {
    return Refusal{400, hosts == 0 ? std::string("the request has no Host header")
                                   : "the request has " + std::to_string(hosts) + " Host headers; send one"};
  }
  const std::string host_header = req.get_header_value("Host");
  const std::optional<HostHeader> host = parseHost(host_header);
  if (!host) return Refusal{400, "the Host header is not HOST or HOST:PORT (Host: " + quoted(host_header) + ")"};
  if (loopback_only) {
    // A page on another site whose name resolves to 127.0.0.1 (DNS rebinding) sends its own Host.
    if (!isLoopbackName(host->name)) {
      return Refusal{403,
                     "this server answers requests to 127.0.0.1 or localhost only (Host: " + quoted(host_header) + ")"};
    }
  }
  if (host->port != 0 && port > 0 && host->port != port) {
    return Refusal{403, "this server answers on port " + std::to_string(port) + " only (Host: " + quoted(host_header) +
                            "); a tunnel must keep the port"};
  }
  if (!isValidUtf8(req.path)) return Refusal{400, "the path is not valid UTF-8"};
  for (const auto& [name, value] : req.params) {
    if (!isValidUtf8(name) || !isValidUtf8(value)) {
      return Refusal{400, "query parameter '" + quoted(name) + "' is not valid UTF-8"};
    }
  }
  if (changesSomething(req.method)) {
    if (req.has_header("Origin")) {
      const std::string origin = req.get_header_value("Origin");
      if (host_header.empty() || lower(origin) != "http://" + lower(host_header)) {
        return Refusal{403, "cross-origin request refused (Origin: " + quoted(origin) +
                                "); this API answers changes from its own pages only"};
      }
    }
    if (req.has_header("Sec-Fetch-Site")) {
      const std::string site = lower(req.get_header_value("Sec-Fetch-Site"));
      if (site != "same-origin" && site != "none") {
        return Refusal{403, "cross-site request refused (Sec-Fetch-Site: " + quoted(site) +
                                "); this API answers changes from its own pages only"};
      }
    }
  }
  return std::nullopt;
}

}  // namespace dash::http
