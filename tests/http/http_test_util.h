#pragma once
// Shared by the HTTP tests: a temporary folder, a results database with a few recorded runs (a
// solved one with the contract's example plan, a timeout, task-only runs), the server started in
// this process on a free loopback port, and small HTTP helpers (with or without the token).
#include <gtest/gtest.h>

#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "server/http/http_server.h"
#include "tests/common/temp_dir.h"

namespace dash::http::testing {

using Json = nlohmann::json;

inline constexpr const char* kToken = "test-token-0123456789abcdef";

/// The test's own temporary folder (tests/common/temp_dir.h).
using TempDir = dash::test::TempDir;

/// The recorded runs of fixtureDb(): uuids by role.
struct Fixture {
  std::string solved;     ///< lazy-dash, robots=2 objects=2 seed 1, with a plan, constraints, an expansion
  std::string timeout;    ///< lazy-dash, robots=2 objects=4 seed 1, no plan
  std::string task_only;  ///< lazy-task, robots=2 objects=2 seed 2
  std::string batch_id;   ///< the batch all three belong to (finished)
};

/// Records the fixture runs into a new database at `path`.
Fixture fixtureDb(const std::string& path);

/// ServerOptions for tests: port 0, the token, the dashbench binary for runs, the source tree's web/.
ServerOptions testOptions(const std::string& db_path);

struct Reply {
  int status = 0;  ///< 0: no answer
  std::string body;
  std::multimap<std::string, std::string> headers;
  Json json() const { return Json::parse(body, nullptr, false); }
  std::string header(const std::string& name) const;
};

/// HTTP on loopback. `token` empty: no Authorization header.
class Http {
 public:
  explicit Http(int port) : port_(port) {}
  Reply get(const std::string& path, const std::string& token = "") const;
  Reply post(const std::string& path, const std::string& body, const std::string& token = kToken) const;
  Reply put(const std::string& path, const std::string& body, const std::string& token = kToken) const;
  Reply del(const std::string& path, const std::string& token = kToken) const;
  /// Sends `request` as it is over a plain socket (for paths a client library would clean up);
  /// returns the whole answer.
  std::string raw(const std::string& request) const;

 private:
  int port_;
};

/// Polls `done` every 50 ms until it holds or `seconds` pass; returns whether it held.
bool waitFor(const std::function<bool()>& done, double seconds);

/// A batch spec: sorting, robots 2, the given objects list and seeds, one planner entry (JSON).
std::string tinySpec(const std::string& name, const std::string& objects, const std::string& seeds,
                     const std::string& planner_json, double time_limit = 20);
inline constexpr const char* kTaskOnlyPlanner =
    R"({"name":"lazy-dash","settings":{"task_only":true},"label":"lazy-task"})";

/// GET /api/batches/ID until its status is `status` (or `seconds` pass); returns the last batch JSON.
Json waitForBatch(const Http& http, const std::string& id, const std::string& status, double seconds);

/// A server on a fixture database in a temporary folder, for one test.
class ServerTest : public ::testing::Test {
 protected:
  void SetUp() override {
    db_path = dir.file("results.db");
    fixture = fixtureDb(db_path);
    server = std::make_unique<HttpServer>(options());
    http = std::make_unique<Http>(server->start());
  }
  void TearDown() override { server->stop(); }
  /// Override to change the server's options.
  virtual ServerOptions options() { return testOptions(db_path); }

  TempDir dir;
  std::string db_path;
  Fixture fixture;
  std::unique_ptr<HttpServer> server;
  std::unique_ptr<Http> http;
};

}  // namespace dash::http::testing
