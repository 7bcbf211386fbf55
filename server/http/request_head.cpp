#include "server/http/request_head.h"

#include <algorithm>
#include <cctype>

namespace dash::http {

namespace {

bool startsWithName(std::string_view line, std::string_view name) {
  if (line.size() <= name.size() || line[name.size()] != ':') return false;
  for (std::size_t i = 0; i < name.size(); ++i) {
    if (std::tolower(static_cast<unsigned char>(line[i])) != name[i]) return false;
  }
  return true;
}

std::string_view valueOf(std::string_view line) {
  std::string_view v = line.substr(line.find(':') + 1);
  while (!v.empty() && (v.front() == ' ' || v.front() == '\t')) v.remove_prefix(1);
  while (!v.empty() && (v.back() == ' ' || v.back() == '\t')) v.remove_suffix(1);
  return v;
}

std::string lowerText(std::string_view v) {
  std::string s(v);
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

HeadCheck refuse(HeadCheck c, int status, std::string message) {
  c.status = status;
  c.message = std::move(message);
  return c;
}

}  // namespace

HeadCheck inspectHead(std::string_view buffer, const HeadLimits& limits) {
  HeadCheck c;
  // Blank lines before a request line are allowed (RFC 9112 2.2); httplib skips them as well.
  const std::size_t end = buffer.find("\r\n\r\n");
  if (end == std::string_view::npos || end + 4 > limits.max_head_bytes) {
    if (buffer.size() >= limits.max_head_bytes) {
      return refuse(c, 431, "request head larger than " + std::to_string(limits.max_head_bytes) + " bytes");
    }
    return c;
  }
  c.complete = true;
  c.head_bytes = end + 4;
  std::size_t headers = 0;
  bool have_length = false;
  std::size_t pos = buffer.find("\r\n") + 2;  // past the request line
  while (pos < end + 2) {
    const std::size_t eol = buffer.find("\r\n", pos);
    const std::string_view line = buffer.substr(pos, eol - pos);
    pos = eol + 2;
    if (line.empty()) continue;
    if (++headers > limits.max_headers) {
      return refuse(c, 431, "more than " + std::to_string(limits.max_headers) + " request headers");
    }
    if (startsWithName(line, "content-length")) {
      const std::string_view v = valueOf(line);
      if (v.empty() || v.size() > 15 || !std::all_of(v.begin(), v.end(), [](char d) { return d >= '0' && d <= '9'; })) {
        return refuse(c, 400, "malformed Content-Length");
      }
      const std::size_t n = std::stoull(std::string(v));
      if (have_length && n != c.body_bytes) return refuse(c, 400, "conflicting Content-Length headers");
      have_length = true;
      c.body_bytes = n;
    } else if (startsWithName(line, "transfer-encoding")) {
      return refuse(c, 411, "chunked or encoded request bodies are not accepted; send a Content-Length");
    } else if (startsWithName(line, "content-encoding")) {
      if (lowerText(valueOf(line)) != "identity") {
        return refuse(c, 415, "compressed request bodies are not accepted (Content-Encoding)");
      }
    } else if (startsWithName(line, "range")) {
      if (valueOf(line).find(',') != std::string_view::npos) {
        return refuse(c, 416, "one byte range per request");
      }
    } else if (startsWithName(line, "expect")) {
      c.expects_continue = lowerText(valueOf(line)) == "100-continue";
    }
  }
  if (c.body_bytes > limits.max_body_bytes) return refuse(c, 413, "request body too large");
  return c;
}

std::string withoutExpect(std::string_view head) {
  std::string out;
  std::size_t pos = 0;
  while (pos < head.size()) {
    std::size_t eol = head.find("\r\n", pos);
    eol = eol == std::string_view::npos ? head.size() : eol + 2;
    const std::string_view line = head.substr(pos, eol - pos);
    if (!startsWithName(line, "expect")) out += line;
    pos = eol;
  }
  return out;
}

}  // namespace dash::http
