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

bool isTokenChar(char ch) {
  if (std::isalnum(static_cast<unsigned char>(ch)) != 0) return true;
  return std::string_view("!#$%&'*+-.^_`|~").find(ch) != std::string_view::npos;
}

HeadCheck refuse(HeadCheck c, int status, std::string message) {
  c.status = status;
  c.message = std::move(message);
  return c;
}

/// Bare CR or LF in buffer[start, scanned): line ends are CRLF only. httplib reads a bare LF as a line
/// end where this gate would not: a header hidden behind one (a Content-Length) would be seen by one
/// side only.
bool hasBareLineEnd(std::string_view buffer, std::size_t start, std::size_t scanned) {
  for (std::size_t i = start; i < scanned; ++i) {
    const char ch = buffer[i];
    if ((ch == '\n' && (i == 0 || buffer[i - 1] != '\r')) || (ch == '\r' && i + 1 < scanned && buffer[i + 1] != '\n')) {
      return true;
    }
  }
  return false;
}

/// One header line: refused into `c` (true) or noted there (Content-Length, Expect).
bool refuseHeader(std::string_view line, HeadCheck& c, bool& have_length) {
  // "name: value", the name a token: no space before the colon (RFC 9112 5.1), no folded lines,
  // no line without a colon. httplib 0.11.4 reads "Content-Length : 5" as another header.
  const std::size_t colon = line.find(':');
  if (colon == std::string_view::npos || colon == 0 ||
      !std::all_of(line.begin(), line.begin() + static_cast<std::ptrdiff_t>(colon), isTokenChar)) {
    c = refuse(c, 400, "malformed request header line");
    return true;
  }
  if (!std::all_of(line.begin() + static_cast<std::ptrdiff_t>(colon), line.end(), [](char ch) {
        return ch == '\t' || (static_cast<unsigned char>(ch) >= 0x20 && ch != 0x7f);
      })) {
    c = refuse(c, 400, "control character in a request header");
    return true;
  }
  if (startsWithName(line, "content-length")) {
    const std::string_view v = valueOf(line);
    if (v.empty() || v.size() > 15 || !std::all_of(v.begin(), v.end(), [](char d) { return d >= '0' && d <= '9'; })) {
      c = refuse(c, 400, "malformed Content-Length");
      return true;
    }
    // A repeated Content-Length is refused even when equal: one side of a proxy may take another.
    if (have_length) {
      c = refuse(c, 400, "more than one Content-Length header");
      return true;
    }
    have_length = true;
    c.body_bytes = std::stoull(std::string(v));
  } else if (startsWithName(line, "transfer-encoding")) {
    c = refuse(c, 411, "chunked or encoded request bodies are not accepted; send a Content-Length");
    return true;
  } else if (startsWithName(line, "content-encoding")) {
    if (lowerText(valueOf(line)) != "identity") {
      c = refuse(c, 415, "compressed request bodies are not accepted (Content-Encoding)");
      return true;
    }
  } else if (startsWithName(line, "range")) {
    if (valueOf(line).find(',') != std::string_view::npos) {
      c = refuse(c, 416, "one byte range per request");
      return true;
    }
  } else if (startsWithName(line, "expect")) {
    c.expects_continue = lowerText(valueOf(line)) == "100-continue";
  }
  return false;
}

}  // namespace

HeadCheck inspectHead(std::string_view buffer, const HeadLimits& limits) {
  HeadCheck c;
  // Blank lines before a request line are allowed (RFC 9112 2.2); httplib skips them as well. They
  // count as part of this request's head.
  std::size_t start = 0;
  while (buffer.substr(start, 2) == "\r\n") start += 2;
  const std::size_t found = buffer.find("\r\n\r\n", start);
  const std::size_t scanned = found == std::string_view::npos ? buffer.size() : found + 4;
  if (hasBareLineEnd(buffer, start, scanned)) {
    return refuse(c, 400, "bare CR or LF in the request head; lines end with CRLF");
  }
  if (found == std::string_view::npos || found + 4 > limits.max_head_bytes) {
    if (buffer.size() >= limits.max_head_bytes) {
      return refuse(c, 431, "request head larger than " + std::to_string(limits.max_head_bytes) + " bytes");
    }
    return c;
  }
  const std::size_t end = found;
  c.complete = true;
  c.head_bytes = end + 4;
  const std::size_t line_end = buffer.find("\r\n", start);
  const std::string_view request_line = buffer.substr(start, line_end - start);
  if (request_line.empty() || !std::all_of(request_line.begin(), request_line.end(), [](char ch) {
        return static_cast<unsigned char>(ch) >= 0x20 && ch != 0x7f;
      })) {
    return refuse(c, 400, "malformed request line");
  }
  const std::string_view method = request_line.substr(0, request_line.find(' '));
  std::size_t headers = 0;
  bool have_length = false;
  std::size_t pos = line_end + 2;  // past the request line
  while (pos < end + 2) {
    const std::size_t eol = buffer.find("\r\n", pos);
    const std::string_view line = buffer.substr(pos, eol - pos);
    pos = eol + 2;
    if (++headers > limits.max_headers) {
      return refuse(c, 431, "more than " + std::to_string(limits.max_headers) + " request headers");
    }
    if (refuseHeader(line, c, have_length)) return c;
  }
  // httplib reads a body for these methods; without a Content-Length it read until the client
  // closed, with no limit (1000 MB were accepted).
  if (!have_length && (method == "POST" || method == "PUT" || method == "PATCH" || method == "PRI")) {
    return refuse(c, 411, "a " + std::string(method) + " request needs a Content-Length");
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
