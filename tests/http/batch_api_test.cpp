// Batches through the API, run for real (each run a `dashbench run-one` process): validate, submit
// and watch it finish, progress over server-sent events, cancel and resume, a planner crash, and a
// server restart that leaves an unfinished batch resumable.

#include <mutex>
#include <thread>

#include "tests/http/http_test_util.h"

// clang-format off
#include <httplib.h>  // last: it must follow Eigen (see server/dispatch/dispatch_routes.h)
// clang-format on

namespace dash::http::testing {
namespace {

using BatchApiTest = ServerTest;

constexpr const char* kSpinning =
    R"({"name":"lazy-dash","settings":{"test_fault":"ignore-deadline"},"label":"spinning"})";

std::string submit(const Http& http, const std::string& spec, int workers = 1) {
  const Reply r = http.post("/api/batches", Json{{"spec", Json::parse(spec)}, {"workers", workers}}.dump());
  EXPECT_EQ(r.status, 202) << r.body;
  return r.json().value("batch_id", "");
}

TEST_F(BatchApiTest, ValidateCountsRunsAndNamesBadFields) {
  const Reply ok =
      http->post("/api/batches/validate", tinySpec("v", "[2,4]", R"({"from":1,"count":3})", kTaskOnlyPlanner), "");
  ASSERT_EQ(ok.status, 200) << ok.body;
  EXPECT_TRUE(ok.json()["valid"].get<bool>());
  EXPECT_EQ(ok.json()["runs"], 6);
  EXPECT_EQ(ok.json()["keys"][0], "sorting/robots=2,objects=2/seed=1/lazy-task");
  const Reply range = http->post("/api/batches/validate", tinySpec("v", "[2,400]", "[1]", kTaskOnlyPlanner), "");
  EXPECT_EQ(range.status, 200);
  EXPECT_FALSE(range.json()["valid"].get<bool>());
  EXPECT_EQ(range.json()["kind"], "out-of-range");
  EXPECT_NE(range.json()["error"].get<std::string>().find("params.objects"), std::string::npos) << range.body;
  const Reply unknown =
      http->post("/api/batches/validate", R"({"name":"x","scenarios":[],"planners":[],"seeds":[1],"colour":1})", "");
  EXPECT_FALSE(unknown.json()["valid"].get<bool>());
  EXPECT_EQ(http->post("/api/batches/validate", "{not json", "").status, 400);
  EXPECT_EQ(http->post("/api/batches",
                       Json{{"spec", Json::parse(tinySpec("w", "2", "[1]", kTaskOnlyPlanner))}, {"workers", 99}}.dump())
                .status,
            400);
}

TEST_F(BatchApiTest, SubmittedBatchRunsToTheEndAndItsRunsAreListed) {
  const std::string id = submit(*http, tinySpec("api", "2", "[1,2]", kTaskOnlyPlanner), 2);
  ASSERT_FALSE(id.empty());
  const Json b = waitForBatch(*http, id, "finished", 60);
  ASSERT_EQ(b["status"], "finished") << b.dump();
  EXPECT_EQ(b["total"], 2);
  EXPECT_EQ(b["pending"], 0);
  EXPECT_EQ(b["by_status"]["solved"], 2);
  ASSERT_EQ(b["runs"].size(), 2u);
  EXPECT_EQ(b["runs"][0]["status"], "solved");
  EXPECT_FALSE(b["resumable"].get<bool>());
  const Json runs = http->get("/api/runs?batch=" + id).json();
  EXPECT_EQ(runs["total"], 2);
  EXPECT_EQ(runs["runs"][0]["config"], "lazy-task");
  EXPECT_GT(runs["runs"][0]["task_vertices"].get<int>(), 0);
  EXPECT_EQ(http->post("/api/batches/" + id + "/resume", "{}").status, 409) << "nothing is missing";
  EXPECT_EQ(http->post("/api/batches/" + id + "/cancel", "{}").status, 409) << "not running";
  EXPECT_EQ(http->post("/api/batches/nope-1/cancel", "{}").status, 404);
}

TEST_F(BatchApiTest, EventStreamDeliversProgressWhileABatchRuns) {
  std::mutex mutex;
  std::string received;
  httplib::Client client("127.0.0.1", server->port());
  client.set_read_timeout(60, 0);
  std::thread reader([&] {
    client.Get("/api/events", [&](const char* data, std::size_t n) {
      std::lock_guard lock(mutex);
      received.append(data, n);
      return true;
    });
  });
  ASSERT_TRUE(waitFor(
      [&] {
        std::lock_guard lock(mutex);
        return received.find("event: hello") != std::string::npos;
      },
      10));
  const std::string id = submit(*http, tinySpec("sse", "2", "[1,2,3]", kTaskOnlyPlanner));
  const bool finished = waitFor(
      [&] {
        std::lock_guard lock(mutex);
        return received.find("\"status\":\"finished\"") != std::string::npos;
      },
      60);
  client.stop();  // closes the connection: the server notices at its next write
  reader.join();
  ASSERT_TRUE(finished) << received;
  EXPECT_NE(received.find("event: batch\ndata: {\"id\":\"" + id), std::string::npos);
  EXPECT_NE(received.find("\"done\":1,"), std::string::npos) << "progress after the first run";
  EXPECT_NE(received.find("\"done\":3,"), std::string::npos) << "progress after the last run";
  EXPECT_NE(received.find("event: run\n"), std::string::npos) << "run status changes from the watcher";
  EXPECT_NE(received.find("\"status\":\"solved\""), std::string::npos);
  EXPECT_NE(received.find("event: batches\n"), std::string::npos);
}

TEST_F(BatchApiTest, EventStreamShowsARunningPlansSizesGrowing) {
  std::mutex mutex;
  std::string received;
  httplib::Client client("127.0.0.1", server->port());
  client.set_read_timeout(60, 0);
  std::thread reader([&] {
    client.Get("/api/events?topics=sizes", [&](const char* data, std::size_t n) {
      std::lock_guard lock(mutex);
      received.append(data, n);
      return true;
    });
  });
  // Full Lazy-DaSH on four arms plans for seconds (it hits its time limit): long enough to watch.
  const std::string spec = R"({"name":"grow","time_limit":20,"memory_limit":4096,"scenarios":[{"family":"sorting",)"
                           R"("params":{"robots":4,"objects":2}}],"planners":[{"name":"lazy-dash"}],"seeds":[1]})";
  const std::string id = submit(*http, spec);
  auto sizesSeen = [&] {
    std::lock_guard lock(mutex);
    std::size_t count = 0;
    for (std::size_t at = received.find("event: sizes"); at != std::string::npos;
         at = received.find("event: sizes", at + 1)) {
      ++count;
    }
    return count;
  };
  const bool grew = waitFor([&] { return sizesSeen() >= 2; }, 60);
  EXPECT_EQ(http->post("/api/batches/" + id + "/cancel", "{}").status, 202);
  client.stop();
  reader.join();
  ASSERT_TRUE(grew) << received;
  const Json run = http->get("/api/runs?batch=" + id).json()["runs"][0];
  EXPECT_NE(received.find("\"uuid\":\"" + run["uuid"].get<std::string>() + "\""), std::string::npos);
  EXPECT_NE(received.find("\"task_vertices\":"), std::string::npos);
  EXPECT_EQ(received.find("event: batch\n"), std::string::npos) << "only the topics asked for";
  waitForBatch(*http, id, "cancelled", 30);
}

TEST_F(BatchApiTest, CancelThenResume) {
  const std::string id = submit(*http, tinySpec("spin", "2", "[1]", kSpinning, 60));
  ASSERT_TRUE(waitFor(
      [&] { return http->get("/api/runs?batch=" + id + "&q=status%20%3D%20running").json()["total"] == 1; }, 60));
  const Reply c = http->post("/api/batches/" + id + "/cancel", "{}");
  EXPECT_EQ(c.status, 202) << c.body;
  Json b = waitForBatch(*http, id, "cancelled", 30);
  ASSERT_EQ(b["status"], "cancelled") << b.dump();
  EXPECT_TRUE(b["resumable"].get<bool>());
  EXPECT_EQ(b["runs"][0]["status"], "cancelled");
  const Reply r = http->post("/api/batches/" + id + "/resume", R"({"workers":1})");
  EXPECT_EQ(r.status, 202) << r.body;
  ASSERT_TRUE(waitFor([&] { return http->get("/api/batches/" + id).json()["runs"][0]["attempts"] == 2; }, 60));
  EXPECT_EQ(http->post("/api/batches/" + id + "/resume", "{}").status, 409) << "already running here";
  EXPECT_EQ(http->post("/api/batches/" + id + "/cancel", "{}").status, 202);
  b = waitForBatch(*http, id, "cancelled", 30);
  EXPECT_EQ(b["status"], "cancelled");
}

TEST_F(BatchApiTest, APlannerCrashIsRecordedAndTheServerGoesOn) {
  const std::string id = submit(
      *http,
      tinySpec("crash", "2", "[1]", R"({"name":"lazy-dash","settings":{"test_fault":"abort"},"label":"aborting"})"));
  const Json b = waitForBatch(*http, id, "finished", 60);
  ASSERT_EQ(b["status"], "finished") << b.dump();
  EXPECT_EQ(b["runs"][0]["status"], "crashed");
  const Json run = http->get("/api/runs?batch=" + id).json()["runs"][0];
  EXPECT_EQ(run["exit_signal"], 6);
  EXPECT_EQ(http->get("/api/health").status, 200);
}

TEST_F(BatchApiTest, RunsTheAxisStopRuleSkippedAreListedAsSkippedWithWhatTheyAre) {
  // "aborting" crashes at objects=2, so the stop rule skips its objects=4; the task-only planner runs both.
  const std::string spec =
      R"({"name":"stop","time_limit":20,"memory_limit":2048,"scenarios":[{"family":"sorting",)"
      R"("params":{"robots":2,"objects":[2,4]},"stop_axis":"objects"}],"planners":[)"
      R"({"name":"lazy-dash","settings":{"test_fault":"abort"},"label":"aborting"},)" +
      std::string(kTaskOnlyPlanner) + R"(],"seeds":[1]})";
  const std::string id = submit(*http, spec);
  const Json b = waitForBatch(*http, id, "finished", 60);
  ASSERT_EQ(b["status"], "finished") << b.dump();
  int skipped = 0;
  for (const Json& r : b["runs"]) {
    EXPECT_EQ(r["family"], "sorting");
    EXPECT_EQ(r["seed"], 1);
    EXPECT_EQ(r["stop_axis"], "objects");
    EXPECT_EQ(r["params"]["robots"], 2);
    if (r["status"] != "skipped") continue;
    ++skipped;
    EXPECT_EQ(r["config"], "aborting");
    EXPECT_EQ(r["planner"], "lazy-dash");
    EXPECT_EQ(r["params"]["objects"], 4);
    EXPECT_TRUE(r["uuid"].is_null());
    EXPECT_NE(r["skipped"].get<std::string>().find("objects=2"), std::string::npos) << r.dump();
  }
  EXPECT_EQ(skipped, 1) << b.dump();
}

struct OneAtATime : BatchApiTest {
  ServerOptions options() override {
    ServerOptions o = testOptions(db_path);
    o.max_running_batches = 1;
    return o;
  }
};

TEST_F(OneAtATime, AfterARestartUnfinishedBatchesAreResumable) {
  const std::string running = submit(*http, tinySpec("first", "2", "[1]", kSpinning, 60));
  const std::string queued = submit(*http, tinySpec("second", "2", "[1,2]", kTaskOnlyPlanner));
  // Its run started (the batch is "running" a moment before its worker takes the run).
  ASSERT_TRUE(waitFor(
      [&] {
        const Json b = http->get("/api/batches/" + running).json();
        return b["status"] == "running" && b["runs"][0]["status"] == "running";
      },
      30));
  EXPECT_EQ(http->get("/api/batches/" + queued).json()["status"], "queued");
  server->stop();  // what Ctrl-C does: the running batch is stopped, the queued one never started

  server = std::make_unique<HttpServer>(testOptions(db_path));
  http = std::make_unique<Http>(server->start());
  Json second = http->get("/api/batches/" + queued).json();
  EXPECT_EQ(second["status"], "interrupted") << second.dump();
  EXPECT_TRUE(second["resumable"].get<bool>());
  EXPECT_EQ(second["pending"], 2);
  const Json first = http->get("/api/batches/" + running).json();
  EXPECT_EQ(first["status"], "interrupted") << "stopped with the server, not cancelled by anyone";
  EXPECT_TRUE(first["resumable"].get<bool>());
  EXPECT_EQ(first["runs"][0]["status"], "cancelled") << "its run is re-run by a resume";
  ASSERT_EQ(http->post("/api/batches/" + queued + "/resume", "{}").status, 202);
  second = waitForBatch(*http, queued, "finished", 60);
  EXPECT_EQ(second["by_status"]["solved"], 2) << second.dump();
}

}  // namespace
}  // namespace dash::http::testing
