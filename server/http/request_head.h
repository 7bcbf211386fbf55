#pragma once
// RequestHead: what the connection gate reads of a request before a worker thread sees it. It
// works on the raw bytes of one request head ("GET / HTTP/1.1\r\nHost: ...\r\n\r\n") and decides
// whether the request may go on, and how many body bytes must be buffered first.
//
// Limits cpp-httplib 0.11.4 does not have (issue 24): a header count and a head size (it accepted
// 300,000 headers), and bodies counted before decoding: chunked transfer encoding and content
// encodings are refused (they bypassed the body limit: 50 MB chunked, 51 KB of gzip inflating to
// 50 MB), so every body has a Content-Length the limit applies to. More than one byte range per
// request is refused too (httplib builds a multi-range answer in memory).
#include <cstddef>
#include <string>
#include <string_view>

namespace dash::http {

struct HeadLimits {
  std::size_t max_head_bytes = 64 * 1024;  ///< request line and headers
  std::size_t max_headers = 100;
  std::size_t max_body_bytes = 1 << 20;
};

struct HeadCheck {
  bool complete = false;          ///< the blank line that ends the head has arrived
  int status = 0;                 ///< 0: accepted; else the 4xx to answer (then close)
  std::string message;            ///< why, for the {"error": ...} answer
  std::size_t head_bytes = 0;     ///< up to and including the blank line
  std::size_t body_bytes = 0;     ///< Content-Length
  bool expects_continue = false;  ///< "Expect: 100-continue"
};

/// Inspects the start of `buffer` (it may hold more than one request).
HeadCheck inspectHead(std::string_view buffer, const HeadLimits& limits);

/// `head` without its Expect header lines (the gate answered 100 Continue itself).
std::string withoutExpect(std::string_view head);

}  // namespace dash::http
