// The connection gate's and the pre-routing checks' parts, without a server: request heads, JSON
// depth, UTF-8.
#include <gtest/gtest.h>

#include "server/http/json_depth.h"
#include "server/http/request_guard.h"
#include "server/http/request_head.h"

namespace dash::http {
namespace {

TEST(RequestHead, WaitsForTheBlankLineAndReadsTheLength) {
  const HeadLimits limits;
  EXPECT_FALSE(inspectHead("GET / HTTP/1.1\r\nHost: x\r\n", limits).complete);
  const HeadCheck get = inspectHead("GET / HTTP/1.1\r\nHost: x\r\n\r\nGET /next", limits);
  EXPECT_TRUE(get.complete);
  EXPECT_EQ(get.status, 0);
  EXPECT_EQ(get.head_bytes, 27u);
  EXPECT_EQ(get.body_bytes, 0u);
  const HeadCheck post =
      inspectHead("POST /a HTTP/1.1\r\ncontent-LENGTH:  12 \r\nExpect: 100-continue\r\n\r\n", limits);
  EXPECT_EQ(post.status, 0);
  EXPECT_EQ(post.body_bytes, 12u);
  EXPECT_TRUE(post.expects_continue);
}

TEST(RequestHead, RefusesWhatBypassedTheLimits) {
  const HeadLimits limits{.max_head_bytes = 1024, .max_headers = 3, .max_body_bytes = 100};
  EXPECT_EQ(inspectHead("POST / HTTP/1.1\r\nTransfer-Encoding: chunked\r\n\r\n", limits).status, 411);
  EXPECT_EQ(inspectHead("POST / HTTP/1.1\r\nContent-Encoding: gzip\r\n\r\n", limits).status, 415);
  EXPECT_EQ(inspectHead("POST / HTTP/1.1\r\nContent-Encoding: identity\r\nContent-Length: 0\r\n\r\n", limits).status, 0);
  EXPECT_EQ(inspectHead("POST / HTTP/1.1\r\nContent-Length: 101\r\n\r\n", limits).status, 413);
  EXPECT_EQ(inspectHead("POST / HTTP/1.1\r\nContent-Length: 1\r\nContent-Length: 2\r\n\r\n", limits).status, 400);
  EXPECT_EQ(inspectHead("POST / HTTP/1.1\r\nContent-Length: -1\r\n\r\n", limits).status, 400);
  EXPECT_EQ(inspectHead("POST / HTTP/1.1\r\nContent-Length: 99999999999999999999\r\n\r\n", limits).status, 400);
  EXPECT_EQ(inspectHead("GET / HTTP/1.1\r\na: 1\r\nb: 2\r\nc: 3\r\nd: 4\r\n\r\n", limits).status, 431);
  EXPECT_EQ(inspectHead("GET / HTTP/1.1\r\nRange: bytes=0-1,2-3\r\n\r\n", limits).status, 416);
  EXPECT_EQ(inspectHead("GET / HTTP/1.1\r\nRange: bytes=0-1\r\n\r\n", limits).status, 0);
  EXPECT_EQ(inspectHead("GET / HTTP/1.1\r\nX: " + std::string(2000, 'a'), limits).status, 431)
      << "an unfinished head past the size limit";
}

TEST(RequestHead, RefusesAmbiguousHeads) {
  const HeadLimits limits;
  // A body-carrying method without a Content-Length: httplib would read until the client closed.
  for (const char* method : {"POST", "PUT", "PATCH", "PRI"}) {
    EXPECT_EQ(inspectHead(std::string(method) + " /a HTTP/1.1\r\nHost: x\r\n\r\n", limits).status, 411) << method;
  }
  EXPECT_EQ(inspectHead("DELETE /a HTTP/1.1\r\nHost: x\r\n\r\n", limits).status, 0) << "read as an empty body";
  EXPECT_EQ(inspectHead("POST /a HTTP/1.1\r\nContent-Length : 5\r\n\r\nabcde", limits).status, 400);
  EXPECT_EQ(inspectHead("POST /a HTTP/1.1\r\nContent-Length\t: 5\r\n\r\nabcde", limits).status, 400);
  EXPECT_EQ(inspectHead("POST /a HTTP/1.1\r\nTransfer-Encoding : chunked\r\n\r\n", limits).status, 400);
  EXPECT_EQ(inspectHead("GET / HTTP/1.1\r\nno colon here\r\n\r\n", limits).status, 400);
  EXPECT_EQ(inspectHead("GET / HTTP/1.1\r\n: empty name\r\n\r\n", limits).status, 400);
  EXPECT_EQ(inspectHead("GET / HTTP/1.1\r\nA: b\r\n folded\r\n\r\n", limits).status, 400);
  EXPECT_EQ(inspectHead("GET / HTTP/1.1\r\nA: b\x01c\r\n\r\n", limits).status, 400);
  EXPECT_EQ(inspectHead("POST / HTTP/1.1\r\nContent-Length: 2\r\nContent-Length: 2\r\n\r\nab", limits).status, 400);
  EXPECT_EQ(inspectHead("POST / HTTP/1.1\r\nContent-Length: 2, 2\r\n\r\nab", limits).status, 400);
  // Bare line ends: refused as soon as one arrives, not when a CRLF CRLF never comes.
  EXPECT_EQ(inspectHead("GET / HTTP/1.1\nHost: x\n", limits).status, 400);
  EXPECT_EQ(inspectHead("GET / HTTP/1.1\r\nA: b\nContent-Length: 5\r\n\r\n", limits).status, 400);
  EXPECT_EQ(inspectHead("GET / HTTP/1.1\r\nA: b\rC: d\r\n\r\n", limits).status, 400);
  // Blank lines before the request line are skipped and count as head bytes.
  const HeadCheck blank = inspectHead("\r\n\r\nGET / HTTP/1.1\r\nHost: x\r\n\r\n", limits);
  EXPECT_EQ(blank.status, 0);
  EXPECT_EQ(blank.head_bytes, 31u);
}

TEST(RequestHead, WithoutExpectKeepsTheOtherLines) {
  EXPECT_EQ(withoutExpect("POST / HTTP/1.1\r\nExpect: 100-continue\r\nA: b\r\n\r\n"),
            "POST / HTTP/1.1\r\nA: b\r\n\r\n");
}

TEST(JsonDepth, CountsOutsideStringsAndStopsEarly) {
  EXPECT_EQ(jsonNestingDepth(R"({"a": [1, {"b": "[[[["}]})"), 3u);
  EXPECT_EQ(jsonNestingDepth(R"(["\"[[[", []])"), 2u);
  EXPECT_EQ(jsonNestingDepth("1"), 0u);
  EXPECT_EQ(jsonNestingDepth(std::string(100000, '['), 10), 10u);
  EXPECT_FALSE(jsonTooDeep(std::string(kMaxJsonDepth, '[')));
  EXPECT_TRUE(jsonTooDeep(std::string(kMaxJsonDepth + 1, '[')));
}

TEST(Utf8, AcceptsWellFormedOnly) {
  EXPECT_TRUE(isValidUtf8("plain ascii"));
  EXPECT_TRUE(isValidUtf8("caf\xC3\xA9 \xE2\x82\xAC \xF0\x9F\x98\x80"));
  EXPECT_FALSE(isValidUtf8("\xFF"));
  EXPECT_FALSE(isValidUtf8("\xC0\xAF")) << "overlong /";
  EXPECT_FALSE(isValidUtf8("\xED\xA0\x80")) << "surrogate";
  EXPECT_FALSE(isValidUtf8("\xF4\x90\x80\x80")) << "past U+10FFFF";
  EXPECT_FALSE(isValidUtf8("\xE2\x82")) << "cut short";
}

TEST(RequestGuard, HostNames) {
  EXPECT_TRUE(isLoopbackName("LocalHost"));
  EXPECT_TRUE(isLoopbackName("[::1]"));
  EXPECT_FALSE(isLoopbackName("127.0.0.1.evil.example"));
  EXPECT_EQ(hostName("[::1]:8080"), "[::1]");
  EXPECT_EQ(hostName("localhost:8080"), "localhost");
}

}  // namespace
}  // namespace dash::http
