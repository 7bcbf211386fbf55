// A fuzz pass over every route (issue 24): a few thousand random and mutated JSON bodies and query
// strings, with a fixed seed. Every answer must be a 2xx or 4xx (never a 5xx, never none), the
// server must answer a GET within a second afterwards, and the results database must pass
// PRAGMA integrity_check. Routes that would launch work (batch submission, dispatch) are sent
// without the token, so they are parsed and refused, not run.
#include <sqlite3.h>

#include <random>
#include <string>
#include <vector>

#include "tests/http/http_test_util.h"
#include "tests/http/raw_connection.h"

// clang-format off
#include <httplib.h>  // last: it must follow Eigen (see server/dispatch/dispatch_routes.h)
// clang-format on

namespace dash::http::testing {
namespace {

constexpr int kRequests = 3000;
constexpr std::uint32_t kSeed = 20261125;

struct Route {
  std::string method;
  std::string path;  ///< RUN and BATCH are replaced by the fixture's ids (or mutated ones)
  bool with_token = false;
};

std::vector<Route> routes() {
  return {
      {"GET", "/api/health"},
      {"GET", "/api/info"},
      {"GET", "/api/scenarios"},
      {"GET", "/api/scenarios/sorting"},
      {"GET", "/api/robots"},
      {"GET", "/api/planners"},
      {"GET", "/api/series"},
      {"GET", "/api/compare/overview"},
      {"GET", "/api/query/examples"},
      {"POST", "/api/query"},
      {"GET", "/api/runs/columns"},
      {"GET", "/api/runs"},
      {"GET", "/api/runs.csv"},
      {"GET", "/api/runs/RUN"},
      {"GET", "/api/runs/RUN/events"},
      {"GET", "/api/runs/RUN/timeline"},
      {"GET", "/api/runs/RUN/plan"},
      {"GET", "/api/runs/RUN/scene"},
      {"POST", "/api/runs/RUN/tags", true},
      {"DELETE", "/api/runs/RUN/tags/TAG", true},
      {"PUT", "/api/runs/RUN/note", true},
      {"POST", "/api/batches/validate"},
      {"POST", "/api/batches"},
      {"GET", "/api/batches"},
      {"GET", "/api/batches/backends"},
      {"GET", "/api/batches/BATCH"},
      {"POST", "/api/batches/BATCH/cancel", true},
      {"POST", "/api/batches/BATCH/resume", true},
      {"GET", "/api/dispatches"},
      {"GET", "/api/dispatches/x"},
      {"GET", "/api/controllers"},
      {"POST", "/api/controllers/ur5e_0/state"},
      {"POST", "/api/dispatch"},
      {"POST", "/api/dispatch/preflight"},
      {"POST", "/api/dispatch/abort"},
      {"GET", "/api/dispatch"},
      {"GET", "/"},
      {"GET", "/js/app.js"},
      {"GET", "/vendor/three/three.module.js"},
      {"GET", "/api/nothing"},
  };
}

class Fuzzer {
 public:
  explicit Fuzzer(const Fixture& fixture) : rng_(kSeed), fixture_(fixture) {}

  std::size_t pick(std::size_t n) { return std::uniform_int_distribution<std::size_t>(0, n - 1)(rng_); }
  bool chance(double p) { return std::bernoulli_distribution(p)(rng_); }

  std::string randomBytes(std::size_t max) {
    std::string s(pick(max + 1), ' ');
    for (char& c : s) c = static_cast<char>(pick(256));
    return s;
  }

  std::string randomString() {
    static const std::vector<std::string> words = {
        "sorting", "lazy-dash", "solved", "objects", "robots", "'",      "\"",    "%",  "\\u0000",
        "\xff",    "\xc0\xaf",  "..",     "/",       "%00",    "SELECT", "1e400", "-1", "18446744073709551616"};
    std::string s;
    for (std::size_t i = pick(4); i > 0; --i) s += chance(0.8) ? words[pick(words.size())] : randomBytes(8);
    return s;
  }

  Json randomJson(int depth) {
    switch (depth <= 0 ? pick(5) : pick(7)) {
      case 0:
        return nullptr;
      case 1:
        return chance(0.5);
      case 2: {
        static const std::vector<double> numbers = {0, -1, 1e308, -1e-308, 4294967297.0, 0.5, 1e15, 2};
        return chance(0.5) ? Json(numbers[pick(numbers.size())]) : Json(static_cast<std::int64_t>(rng_()));
      }
      case 3: {
        std::string s = randomString();
        return Json(std::string(s.begin(), s.end()));
      }
      case 4:
        return Json(static_cast<std::uint64_t>(rng_()) << 32 | rng_());
      case 5: {
        Json a = Json::array();
        for (std::size_t i = pick(5); i > 0; --i) a.push_back(randomJson(depth - 1));
        return a;
      }
      default: {
        static const std::vector<std::string> keys = {
            "spec",     "workers", "sql",        "max_rows", "tag",   "note", "name",   "scenarios",
            "planners", "seeds",   "time_limit", "backend",  "slurm", "run",  "robots", "plan"};
        Json o = Json::object();
        for (std::size_t i = pick(5); i > 0; --i) o[keys[pick(keys.size())]] = randomJson(depth - 1);
        return o;
      }
    }
  }

  std::string mutate(std::string s) {
    for (std::size_t n = 1 + pick(4); n > 0 && !s.empty(); --n) {
      const std::size_t at = pick(s.size());
      switch (pick(5)) {
        case 0:
          s[at] = static_cast<char>(pick(256));
          break;
        case 1:
          s.erase(at, pick(8));
          break;
        case 2:
          s.insert(at, randomBytes(6));
          break;
        case 3:
          s.insert(at, s.substr(at, pick(40)));
          break;
        default:
          s.resize(at);
          break;
      }
    }
    return s;
  }

  std::string validBody(const std::string& path) {
    if (path == "/api/query") {
      static const std::vector<std::string> sql = {
          "SELECT * FROM dash_runs",
          "SELECT count(*) FROM dash_events",
          "SELECT printf('%.*c', 9000000, 'x')",
          "WITH RECURSIVE c(i) AS (SELECT 1 UNION ALL SELECT i+1 FROM c) SELECT i FROM c",
          "SELECT zeroblob(1000000000)",
          "PRAGMA table_info(dash_runs)",
          "SELECT fts3_tokenizer('simple')",
          "DELETE FROM dash_runs",
          "SELECT hex(randomblob(100000))"};
      return Json{{"sql", sql[pick(sql.size())]}, {"max_rows", 1 + pick(100)}}.dump();
    }
    if (path.find("/tags") != std::string::npos) return jsonText(Json{{"tag", randomString()}});
    if (path.find("/note") != std::string::npos) return jsonText(Json{{"note", randomString()}});
    if (path.find("/api/batches") == 0) {
      const std::string spec = tinySpec("fuzz", "[2]", "[1]", kTaskOnlyPlanner);
      return chance(0.5) ? spec : "{\"spec\": " + spec + ", \"workers\": 2}";
    }
    return jsonText(randomJson(3));
  }

  static std::string jsonText(const Json& j) { return j.dump(-1, ' ', false, Json::error_handler_t::replace); }

  std::string body(const std::string& path) {
    switch (pick(4)) {
      case 0:
        return jsonText(randomJson(4));
      case 1:
        return mutate(validBody(path));
      case 2:
        return validBody(path);
      default:
        return chance(0.5) ? randomBytes(200) : std::string(1 + pick(400), '[');
    }
  }

  std::string escape(const std::string& s) {
    static const char* hex = "0123456789ABCDEF";
    std::string out;
    for (const char c : s) {
      const auto u = static_cast<unsigned char>(c);
      if (std::isalnum(u) || c == '-' || c == '_' || c == '.') {
        out += c;
      } else {
        out += '%';
        out += hex[u >> 4];
        out += hex[u & 15];
      }
    }
    return out;
  }

  std::string query() {
    static const std::vector<std::string> names = {
        "q",      "family", "x",       "group_by",         "split",   "limit", "offset", "sort", "order", "type",
        "topics", "run",    "workers", "include_unsolved", "columns", "kind"};
    std::string q;
    for (std::size_t i = pick(4); i > 0; --i) {
      q += q.empty() ? "?" : "&";
      q += names[pick(names.size())] + "=" +
           escape(chance(0.3) ? std::to_string(static_cast<std::int32_t>(rng_())) : randomString());
    }
    return q;
  }

  std::string path(const Route& route) {
    std::string p = route.path;
    auto replace = [&](const std::string& what, const std::string& with) {
      if (const std::size_t at = p.find(what); at != std::string::npos) p.replace(at, what.size(), with);
    };
    replace("RUN", chance(0.7) ? fixture_.solved : escape(mutate(fixture_.solved)));
    replace("BATCH", chance(0.7) ? fixture_.batch_id : escape(randomString()));
    replace("TAG", escape(randomString()).substr(0, 60) + "t");
    return p + (chance(0.6) ? query() : "");
  }

 private:
  std::mt19937 rng_;
  const Fixture& fixture_;
};

using FuzzTest = ServerTest;

TEST_F(FuzzTest, RandomAndMutatedRequestsOnEveryRoute) {
  Fuzzer fuzz(fixture);
  const std::vector<Route> all = routes();
  httplib::Client client("127.0.0.1", server->port());  // one kept-alive connection, as a page would
  client.set_read_timeout(15, 0);
  client.set_keep_alive(true);
  client.set_tcp_nodelay(true);  // head and body are two writes: without it each POST waits 40 ms
  int answered = 0;
  std::string previous;
  for (int i = 0; i < kRequests; ++i) {
    const Route& route = all[static_cast<std::size_t>(i) % all.size()];
    const std::string path = fuzz.path(route);
    httplib::Headers headers;
    if (route.with_token) headers.emplace("Authorization", std::string("Bearer ") + kToken);
    const httplib::Result r = [&] {
      if (route.method == "GET") return client.Get(path, headers);
      if (route.method == "DELETE") return client.Delete(path, headers);
      const std::string body = fuzz.body(route.path);
      return route.method == "PUT" ? client.Put(path, headers, body, "application/json")
                                   : client.Post(path, headers, body, "application/json");
    }();
    ASSERT_TRUE(r) << route.method << " " << path << ": no answer (" << httplib::to_string(r.error()) << ") after "
                   << previous;
    previous = route.method + " " + path + " -> " + std::to_string(r->status) + " " + r->get_header_value("Connection");
    EXPECT_GE(r->status, 200) << route.method << " " << path;
    EXPECT_LT(r->status, 500) << route.method << " " << path << ": " << r->body.substr(0, 300);
    answered += r->status < 500;
  }
  EXPECT_EQ(answered, kRequests);

  RawConnection c(server->port());
  c.send("GET /api/runs HTTP/1.1\r\nHost: 127.0.0.1\r\nConnection: close\r\n\r\n");
  EXPECT_EQ(RawConnection::statusOf(c.readUntil("\r\n\r\n", 1.0)), 200) << "no answer within 1 s after the fuzz pass";

  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open_v2(db_path.c_str(), &db, SQLITE_OPEN_READONLY, nullptr), SQLITE_OK);
  sqlite3_stmt* stmt = nullptr;
  ASSERT_EQ(sqlite3_prepare_v2(db, "PRAGMA integrity_check", -1, &stmt, nullptr), SQLITE_OK);
  ASSERT_EQ(sqlite3_step(stmt), SQLITE_ROW);
  EXPECT_STREQ(reinterpret_cast<const char*>(sqlite3_column_text(stmt, 0)), "ok");
  sqlite3_finalize(stmt);
  sqlite3_close(db);
}

// Request heads a client library would not send, mutated at random from a few valid ones: header
// names with blanks before the colon, missing or repeated Content-Length, odd methods and versions,
// bare LF or CR, NUL and control bytes, huge header lines, blank lines before the request line.
TEST_F(FuzzTest, MutatedRequestHeadsOnRawSockets) {
  std::mt19937 rng(24);
  auto pick = [&](const std::vector<std::string>& options) {
    return options[std::uniform_int_distribution<std::size_t>(0, options.size() - 1)(rng)];
  };
  const std::vector<std::string> methods = {"GET", "POST", "PUT", "PATCH", "DELETE", "HEAD", "OPTIONS", "TRACE",
                                            "CONNECT", "PRI", "get", "FOO", "G ET", std::string(300, 'G'), ""};
  const std::vector<std::string> targets = {"/api/health", "/api/query", "/api/runs", "/api/batches/validate",
                                            "/index.html", "*", "http://127.0.0.1/api/health", "/%00", "//"};
  const std::vector<std::string> versions = {"HTTP/1.1", "HTTP/1.0", "HTTP/2.0", "HTTP/0.9", "HTTP/1.1 x", ""};
  const std::string body = R"({"sql": "SELECT 1"})";
  const std::string length = std::to_string(body.size());
  const std::vector<std::string> extras = {
      "",
      "Content-Length: " + length + "\r\n",
      "Content-Length : " + length + "\r\n",
      "Content-Length\t: " + length + "\r\n",
      " Content-Length: " + length + "\r\n",
      "Content-Length: " + length + "\r\nContent-Length: " + length + "\r\n",
      "Content-Length: " + length + "\r\nContent-Length: 1\r\n",
      "Content-Length: +" + length + "\r\n",
      "Content-Length: " + length + ", " + length + "\r\n",
      "Transfer-Encoding : chunked\r\n",
      "Transfer-Encoding: chunked\r\n",
      "No colon here\r\n",
      "X-A: b\nContent-Length: 5\r\n",
      "X-A: b\rX-B: c\r\n",
      std::string("X-Nul: a") + '\0' + "b\r\n",
      "X-Ctl: \x01\x7f\r\n",
      "X-Fold: a\r\n  folded\r\n",
      "X-Huge: " + std::string(70000, 'h') + "\r\n",
      "X-Long: " + std::string(8000, 'l') + "\r\n",
      ": empty-name\r\n",
      "Expect: 100-continue\r\nContent-Length: " + length + "\r\n",
      "Content-Type: application/json\r\n",
  };
  int answered = 0;
  constexpr int kHeads = 300;
  for (int i = 0; i < kHeads; ++i) {
    std::string head = (i % 17 == 0 ? "\r\n\r\n" : "") + pick(methods) + " " + pick(targets) + " " + pick(versions) +
                       "\r\nHost: 127.0.0.1\r\n";
    for (int k = std::uniform_int_distribution<int>(0, 3)(rng); k > 0; --k) head += pick(extras);
    head += "Connection: close\r\n\r\n";
    if (i % 5 == 0) {  // bare LF line ends throughout
      std::string lf;
      for (std::size_t j = 0; j < head.size(); ++j) {
        if (head.compare(j, 2, "\r\n") != 0) lf += head[j];
      }
      head = lf;
    }
    RawConnection c(server->port());
    ASSERT_TRUE(c.connected());
    c.send(head + body);
    std::string answer = c.readUntil("\r\n\r\n", 3);
    if (RawConnection::statusOf(answer) == 100) {  // Expect: 100-continue; the final answer follows
      answer = c.readAll(3).substr(answer.find("\r\n\r\n") + 4);
    }
    const int status = RawConnection::statusOf(answer);
    const bool allowed = (status >= 200 && status < 500) || status == 503;
    EXPECT_TRUE(allowed) << status << " for " << head.substr(0, 200);
    answered += allowed;
  }
  EXPECT_EQ(answered, kHeads);
  RawConnection c(server->port());
  c.send("GET /api/health HTTP/1.1\r\nHost: 127.0.0.1\r\nConnection: close\r\n\r\n");
  EXPECT_EQ(RawConnection::statusOf(c.readUntil("\r\n\r\n", 1.0)), 200) << "no answer within 1 s afterwards";
}

}  // namespace
}  // namespace dash::http::testing
