// The server's safety rules: token on every change, clear 4xx JSON errors for bad bodies, a body
// size limit, no path traversal, no CORS, a Host check against DNS rebinding, static files with a
// content security policy, and errors that never take the server down.
#include <filesystem>

#include "tests/http/http_test_util.h"

namespace dash::http::testing {
namespace {

using SecurityTest = ServerTest;

TEST_F(SecurityTest, ChangesNeedTheToken) {
  const std::string spec = tinySpec("t", "2", "[1]", kTaskOnlyPlanner);
  const Reply none = http->post("/api/batches", spec, "");
  EXPECT_EQ(none.status, 401);
  EXPECT_NE(none.json()["error"].get<std::string>().find("Authorization: Bearer"), std::string::npos);
  EXPECT_EQ(http->post("/api/batches", spec, "not-the-token").status, 401);
  EXPECT_EQ(http->post("/api/batches/" + fixture.batch_id + "/cancel", "{}", "").status, 401);
  EXPECT_EQ(http->post("/api/batches/" + fixture.batch_id + "/resume", "{}", "").status, 401);
  EXPECT_EQ(http->del("/api/runs/" + fixture.solved + "/tags/x", "").status, 401);
  EXPECT_EQ(http->post("/api/dispatch/abort", "{}", "").status, server->dispatchMounted() ? 401 : 404);
  EXPECT_EQ(http->get("/api/batches").json()["batches"].size(), 1u) << "nothing was launched";
}

TEST_F(SecurityTest, TheTokenRouteAcceptsOnlyThisServersToken) {
  const Reply right = http->get("/api/token", kToken);
  EXPECT_EQ(right.status, 200) << right.body;
  EXPECT_EQ(right.json()["valid"], true) << right.body;
  const Reply wrong = http->get("/api/token", "not-the-token");
  EXPECT_EQ(wrong.status, 401);
  EXPECT_NE(wrong.json()["error"].get<std::string>().find("wrong token"), std::string::npos) << wrong.body;
  EXPECT_EQ(http->get("/api/token").status, 401);
}

TEST_F(SecurityTest, BadBodiesGetClearJsonErrors) {
  const Reply not_json = http->post("/api/batches", "{\"name\": ");
  EXPECT_EQ(not_json.status, 400);
  EXPECT_NE(not_json.json()["error"].get<std::string>().find("not valid JSON"), std::string::npos);
  EXPECT_EQ(http->post("/api/batches", "").status, 400);
  EXPECT_EQ(http->post("/api/batches", "[1,2]").status, 400);
  const Reply bad_spec = http->post("/api/batches", tinySpec("t", "[300]", "[1]", kTaskOnlyPlanner));
  EXPECT_EQ(bad_spec.status, 400);
  EXPECT_NE(bad_spec.json()["error"].get<std::string>().find("objects"), std::string::npos) << bad_spec.body;
  EXPECT_EQ(bad_spec.json()["kind"], "out-of-range") << bad_spec.body;
}

TEST_F(SecurityTest, TooLargeBodiesAreRefused) {
  const std::string big = "{\"sql\": \"" + std::string(100 * 1024, ' ') + "SELECT 1\"}";
  const Reply r = http->post("/api/query", big);
  EXPECT_EQ(r.status, 413);
  EXPECT_EQ(r.json()["error"], "request body too large");
  EXPECT_EQ(http->get("/api/health").status, 200);
}

TEST_F(SecurityTest, NoPathTraversal) {
  for (const char* path : {"/../../../../etc/passwd", "/%2e%2e/%2e%2e/%2e%2e/etc/passwd", "/js/../../../etc/passwd",
                           "/js/%2e%2e/%2e%2e/%2e%2e/etc/passwd", "/..%2f..%2f..%2fetc%2fpasswd", "/%2fetc%2fpasswd",
                           "/node_modules/three/package.json", "/vendor/../package.json", "/.%2e/.%2e/etc/passwd"}) {
    const std::string answer =
        http->raw(std::string("GET ") + path + " HTTP/1.1\r\nHost: 127.0.0.1\r\nConnection: close\r\n\r\n");
    ASSERT_GE(answer.size(), 12u) << path;
    const int status = std::stoi(answer.substr(9, 3));
    EXPECT_GE(status, 400) << path;
    EXPECT_LT(status, 500) << path;
    EXPECT_EQ(answer.find("root:"), std::string::npos) << path;
    EXPECT_EQ(answer.find("\"name\""), std::string::npos) << path << ": a package.json leaked";
  }
}

TEST_F(SecurityTest, StaticFilesAndVendorAllowList) {
  const Reply index = http->get("/");
  ASSERT_EQ(index.status, 200);
  EXPECT_NE(index.body.find("importmap"), std::string::npos);
  EXPECT_NE(index.header("Content-Security-Policy").find("default-src 'self'"), std::string::npos);
  EXPECT_EQ(index.header("X-Content-Type-Options"), "nosniff");
  EXPECT_EQ(http->get("/js/app.js").header("Content-Type"), "text/javascript; charset=utf-8");
  const bool have_modules = std::filesystem::exists(std::string(DASHBENCH_SOURCE_DIR) + "/web/node_modules/three");
  if (have_modules) {
    const Reply three = http->get("/vendor/three/three.module.js");
    EXPECT_EQ(three.status, 200);
    EXPECT_EQ(three.header("Content-Type"), "text/javascript; charset=utf-8");
  }
  EXPECT_EQ(http->get("/vendor/three/package.json").status, 404);
  EXPECT_EQ(http->get("/nothing-here.js").status, 404);
  const Reply api404 = http->get("/api/nothing");
  EXPECT_EQ(api404.status, 404);
  EXPECT_TRUE(api404.json().contains("error"));
  const Reply post404 = http->post("/api/nothing", "{}");
  EXPECT_EQ(post404.status, 404);
  EXPECT_TRUE(post404.json().contains("error"));
}

TEST_F(SecurityTest, StaticFilesCarryAnETagAndAnswer304WhenItMatches) {
  const Reply first = http->get("/js/app.js");
  ASSERT_EQ(first.status, 200);
  const std::string tag = first.header("ETag");
  ASSERT_FALSE(tag.empty()) << "no ETag on a static file";
  EXPECT_EQ(first.header("Cache-Control"), "no-cache");
  const auto ask = [&](const std::string& if_none_match) {
    return http->raw("GET /js/app.js HTTP/1.1\r\nHost: 127.0.0.1\r\nIf-None-Match: " + if_none_match +
                     "\r\nConnection: close\r\n\r\n");
  };
  for (const std::string& header : {tag, "\"other\", " + tag, "W/" + tag, std::string("*")}) {
    const std::string answer = ask(header);
    ASSERT_GE(answer.size(), 12u) << header;
    EXPECT_EQ(answer.substr(9, 3), "304") << header;
    EXPECT_EQ(answer.find("import "), std::string::npos) << header << ": a 304 carried the body";
  }
  const std::string changed = ask("\"0-0\"");
  EXPECT_EQ(changed.substr(9, 3), "200");
  EXPECT_NE(changed.find("import "), std::string::npos);
  EXPECT_NE(http->get("/").header("ETag"), tag) << "two files with one tag";
}

TEST_F(SecurityTest, NoCorsAndOnlyLoopbackHostNames) {
  const std::string answer = http->raw(
      "OPTIONS /api/batches HTTP/1.1\r\nHost: 127.0.0.1\r\nOrigin: http://evil.example\r\n"
      "Access-Control-Request-Method: POST\r\nConnection: close\r\n\r\n");
  EXPECT_EQ(answer.find("Access-Control-Allow"), std::string::npos) << answer;
  const std::string get = http->raw(
      "GET /api/health HTTP/1.1\r\nHost: 127.0.0.1\r\nOrigin: http://evil.example\r\nConnection: close\r\n\r\n");
  EXPECT_NE(get.find("200"), std::string::npos);
  EXPECT_EQ(get.find("Access-Control-Allow"), std::string::npos);
  const std::string rebound =
      http->raw("GET /api/runs HTTP/1.1\r\nHost: evil.example:8080\r\nConnection: close\r\n\r\n");
  EXPECT_EQ(rebound.substr(9, 3), "403") << rebound;
  const std::string port = std::to_string(server->port());
  const std::string local =
      http->raw("GET /api/health HTTP/1.1\r\nHost: localhost:" + port + "\r\nConnection: close\r\n\r\n");
  EXPECT_EQ(local.substr(9, 3), "200");
  // Another port is another server (issue 40: only the allowed host and port are answered).
  const std::string other = http->raw("GET /api/health HTTP/1.1\r\nHost: localhost:1234\r\nConnection: close\r\n\r\n");
  EXPECT_EQ(other.substr(9, 3), "403");
}

TEST_F(SecurityTest, ErrorsInHandlersNeverStopTheServer) {
  // The database disappears under the server and a directory takes its place: every handler that
  // reads it fails; each answers a JSON error and the server keeps serving.
  std::filesystem::remove(db_path);
  std::filesystem::create_directory(db_path);
  for (const char* path : {"/api/runs", "/api/info", "/api/series?family=sorting&x=objects", "/api/batches"}) {
    const Reply r = http->get(path);
    EXPECT_GE(r.status, 500) << path << ": " << r.body;
    EXPECT_TRUE(r.json().contains("error")) << path << ": " << r.body;
  }
  EXPECT_EQ(http->get("/api/health").status, 200);
  EXPECT_EQ(http->get("/").status, 200);
}

}  // namespace
}  // namespace dash::http::testing
