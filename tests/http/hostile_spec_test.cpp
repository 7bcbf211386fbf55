// Issue 40, findings 1, 2, 7 and 10: batch specs as an attack. A token-free validation request
// with a long label and many seeds took the server from 217 to 649 MB; a grid of many combinations
// cost 1.8 s of CPU per request; a label longer than a process's argument limit passed validation
// and crashed every run; 40 submits at once met "database is locked"; the batch list read every
// stored run. Each is replayed here against a server on loopback.
#include <sqlite3.h>

#include <chrono>
#include <cstdio>
#include <future>
#include <string>
#include <thread>
#include <vector>

#include "engine/log/results_db.h"
#include "server/batch/batch_spec.h"
#include "server/batch/batch_store.h"
#include "tests/http/http_test_util.h"
#include "tests/http/raw_connection.h"

namespace dash::http::testing {
namespace {

class HostileSpecTest : public ServerTest {
 protected:
  ServerOptions options() override {
    ServerOptions o = testOptions(db_path);
    o.threads = 64;
    o.max_body_bytes = 1 << 20;
    return o;
  }
  /// The health check every attack must leave working: an answer within a second.
  void expectAlive() const {
    RawConnection c(server->port());
    ASSERT_TRUE(c.connected());
    c.send("GET /api/health HTTP/1.1\r\nHost: 127.0.0.1\r\nConnection: close\r\n\r\n");
    EXPECT_EQ(RawConnection::statusOf(c.readUntil("\r\n\r\n", 1.0)), 200) << "no answer within 1 s";
  }
  Json validate(const std::string& spec) const {
    const Reply r = http->post("/api/batches/validate", spec, "");
    Json j = r.json();
    j["status"] = r.status;
    return j;
  }
};

std::string labelled(const std::string& label, const std::string& seeds, const std::string& name = "l") {
  return tinySpec(name, "2", seeds, R"({"name":"lazy-dash","settings":{"task_only":true},"label":")" + label + "\"}");
}

// 1. A 30 KB label times 5000 seeds was copied into every run's key and label, and the grid was
// expanded twice: 217 -> 649 MB for one request. Names and labels are bounded at validation.
TEST_F(HostileSpecTest, LongLabelsAndNamesAreRefusedWithTheirLimit) {
  const Json label = validate(labelled(std::string(10000, 'x'), R"({"from": 1, "count": 1000})"));
  ASSERT_EQ(label["status"], 200) << label.dump().substr(0, 300);
  EXPECT_FALSE(label["valid"].get<bool>());
  EXPECT_EQ(label["kind"], "bad-value");
  EXPECT_NE(label.value("error", "").find("planners[0].label: is 10000 bytes long, more than the limit of 256"),
            std::string::npos)
      << label.dump().substr(0, 300);
  const Json name = validate(labelled("ok", "[1]", std::string(1000, 'n')));
  EXPECT_FALSE(name["valid"].get<bool>());
  EXPECT_NE(name.value("error", "").find("name: is 1000 bytes long, more than the limit of 128"), std::string::npos)
      << name.dump().substr(0, 300);
  // At the limits, a spec of 5000 runs is valid; its preview lists 200 keys.
  const Json at_limit =
      validate(labelled(std::string(256, 'x'), R"({"from": 1, "count": 5000})", std::string(128, 'n')));
  ASSERT_TRUE(at_limit["valid"].get<bool>()) << at_limit.dump().substr(0, 300);
  EXPECT_EQ(at_limit["runs"], 5000);
  EXPECT_EQ(at_limit["keys"].size(), 200u);
  expectAlive();
}

// 1b. The bytes a grid expands to are bounded from its sizes, before anything is expanded: with the
// run limit raised, 100,000 runs with 256-byte labels are refused by size.
TEST(HostileSpec, TheBytesAGridExpandsToAreBoundedBeforeExpanding) {
  const std::string spec = labelled(std::string(256, 'x'), R"({"from": 1, "count": 100000})");
  try {
    batch::parseBatchSpec(spec, "spec", {.max_runs = 1000000, .check_combinations = false});
    FAIL() << "a grid of 100,000 runs with long labels was accepted";
  } catch (const batch::SpecError& e) {
    EXPECT_EQ(e.kind(), batch::SpecErrorKind::kTooManyRuns);
    EXPECT_NE(std::string(e.what()).find("more than the limit of 32 MB"), std::string::npos) << e.what();
  }
  // The run limit is checked from the seed count, before the seeds are listed.
  try {
    batch::parseBatchSpec(labelled("x", R"({"from": 1, "count": 1000000})"), "spec", {.max_runs = 5000});
    FAIL() << "1,000,000 runs over a limit of 5000 were accepted";
  } catch (const batch::SpecError& e) {
    EXPECT_NE(std::string(e.what()).find("the grid expands to 1000000 runs, more than the limit of 5000"),
              std::string::npos)
        << e.what();
  }
}

// 2. A 3,968-combination grid (an 804-byte body) cost 1.8 s of generator checks per request; 32
// clients saturated both cores. Validations at once are capped (503 with Retry-After beyond), and
// the health check answers while the cap is full.
TEST_F(HostileSpecTest, ValidationsAtOnceAreCappedAndHealthStaysFast) {
  std::string robots = "[", objects = "[";
  for (int r = 2; r <= 32; ++r) robots += std::to_string(r) + (r < 32 ? "," : "]");
  for (int o = 1; o <= 128; ++o) objects += std::to_string(o) + (o < 128 ? "," : "]");
  const std::string spec = R"({"name":"cpu","scenarios":[{"family":"sorting","params":{"robots":)" + robots +
                           R"(,"objects":)" + objects + R"(}}],"planners":[{"name":"lazy-dash"}],"seeds":[1]})";
  const std::string request =
      "POST /api/batches/validate HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: "
      "application/json\r\nContent-Length: " +
      std::to_string(spec.size()) + "\r\nConnection: close\r\n\r\n" + spec;
  std::vector<std::unique_ptr<RawConnection>> clients;
  for (int i = 0; i < 6; ++i) {
    clients.push_back(std::make_unique<RawConnection>(server->port()));
    clients.back()->send(request);
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  expectAlive();
  int ok = 0, busy = 0, retry_after = 0;
  for (auto& c : clients) {
    const std::string answer = c->readAll(60);
    const int status = RawConnection::statusOf(answer);
    ok += status == 200;
    busy += status == 503;
    retry_after += answer.find("Retry-After: 1\r\n") != std::string::npos;
  }
  EXPECT_GE(busy, 1) << "six validations at once all ran";
  EXPECT_EQ(retry_after, busy) << "every 503 says when to retry";
  EXPECT_GE(ok, 2);
  EXPECT_EQ(ok + busy, 6);
  expectAlive();
}

// 7. A 70 KB label passed validation, then every run crashed: its description, passed as an
// argument, was longer than the system allows one. The label limit refuses it at validation, and a
// run at the limits runs.
TEST_F(HostileSpecTest, ALabelLongerThanARunsArgumentIsRefusedAtValidation) {
  const Json r = validate(labelled(std::string(70000, 'x'), "[1]"));
  ASSERT_EQ(r["status"], 200) << r.dump().substr(0, 300);
  EXPECT_FALSE(r["valid"].get<bool>()) << "a label no run can be started with passed validation";
  EXPECT_EQ(r["kind"], "bad-value");
  const Reply submitted = http->post("/api/batches", labelled(std::string(256, 'y'), "[1]", std::string(128, 'n')));
  ASSERT_EQ(submitted.status, 202) << submitted.body;
  const Json batch = waitForBatch(*http, submitted.json()["batch_id"], "finished", 60);
  ASSERT_EQ(batch.value("status", ""), "finished") << batch.dump().substr(0, 500);
  ASSERT_EQ(batch["runs"].size(), 1u);
  EXPECT_EQ(batch["runs"][0]["status"], "solved") << batch["runs"][0].dump();
}

// 10. 40 submits at once: 6-9 answered 503 "database is locked" after about 6 s. Submits now write
// one at a time, each waiting its turn. Sixty submits of 5,000 runs each (300,000 batch runs, about
// 10 s of writing): the server before the fix (c966076) answered 14 of them 503 "results database
// error: statement failed (INSERT INTO dash_batches ...)" after 5.5 s (its busy timeout), over HTTP
// with the same requests (2026-11-27); now every one is accepted.
TEST_F(HostileSpecTest, SixtySubmitsOfFiveThousandRunsAtOnceAreAllAccepted) {
  constexpr int kSubmits = 60;
  std::vector<std::future<Reply>> replies;
  for (int i = 0; i < kSubmits; ++i) {
    replies.push_back(std::async(std::launch::async, [this, i] {
      return http->post("/api/batches",
                        tinySpec("s" + std::to_string(i), "2", R"({"from": 1, "count": 5000})", kTaskOnlyPlanner));
    }));
  }
  int accepted = 0;
  for (auto& r : replies) {
    const Reply reply = r.get();
    accepted += reply.status == 202;
    EXPECT_EQ(reply.status, 202) << reply.body.substr(0, 300);
  }
  EXPECT_EQ(accepted, kSubmits);
  EXPECT_EQ(http->get("/api/batches").json()["batches"].size(), static_cast<std::size_t>(kSubmits + 1));
  server->stop();  // cancels what runs; nothing more to wait for
}

// 10b. GET /api/batches took 3-7 s with 200,000 stored batch runs: it read and parsed every run's
// description. It counts them in SQL now, so a description it cannot read does not matter to it.
TEST_F(HostileSpecTest, TheBatchListCountsRunsWithoutReadingTheirDescriptions) {
  const batch::BatchSpec spec = batch::parseBatchSpec(tinySpec("c", "[2, 3]", "[1]", kTaskOnlyPlanner), "spec");
  {
    log::ResultsDb db(db_path);
    db.putBatch(log::BatchRecord{.id = "counted", .name = "c", .spec_json = spec.json, .status = "cancelled"});
    batch::BatchStore(db_path).addRuns("counted", batch::expandRuns(spec));
  }
  {
    sqlite3* raw = nullptr;
    ASSERT_EQ(sqlite3_open(db_path.c_str(), &raw), SQLITE_OK);
    sqlite3_busy_timeout(raw, 5000);
    EXPECT_EQ(sqlite3_exec(raw, "UPDATE dash_batch_runs SET spec = '{' WHERE batch_id = 'counted' AND ordinal = 1",
                           nullptr, nullptr, nullptr),
              SQLITE_OK);
    sqlite3_close(raw);
  }
  const Reply list = http->get("/api/batches");
  ASSERT_EQ(list.status, 200) << list.body.substr(0, 300);
  bool found = false;
  const Json batches = list.json()["batches"];
  for (const Json& b : batches) {
    if (b["id"] != "counted") continue;
    found = true;
    EXPECT_EQ(b["total"], 2);
    EXPECT_EQ(b["pending"], 2);
    EXPECT_TRUE(b["resumable"].get<bool>());
  }
  EXPECT_TRUE(found) << list.body.substr(0, 300);
}

// 10c. The server refused specs over 5,000 runs while the docs said 10,000, and told people to use
// --max-runs, which `serve` did not have.
TEST_F(HostileSpecTest, TheRunLimitNamesTheServersOption) {
  const Json r = validate(labelled("x", R"({"from": 1, "count": 5001})"));
  EXPECT_FALSE(r["valid"].get<bool>());
  EXPECT_EQ(r["kind"], "too-many-runs");
  EXPECT_NE(r.value("error", "")
                .find("5001 runs, more than the limit of 5000 (this server's limit: dashbench serve "
                      "--max-runs)"),
            std::string::npos)
      << r.dump();
  const std::string help = [] {
    std::string out;
    FILE* p = popen((std::string(DASHBENCH_BINARY) + " serve --help 2>&1").c_str(), "r");
    char buffer[4096];
    while (p != nullptr && std::fgets(buffer, sizeof buffer, p) != nullptr) out += buffer;
    if (p != nullptr) pclose(p);
    return out;
  }();
  EXPECT_NE(help.find("--max-runs N"), std::string::npos) << help;
  EXPECT_NE(help.find("--query-timeout S"), std::string::npos) << help;
}

}  // namespace
}  // namespace dash::http::testing
