#include "tests/http/http_test_util.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <stdlib.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <fstream>
#include <sstream>
#include <thread>

#include "engine/events/event_emitter.h"
#include "engine/log/results_db.h"
#include "engine/log/sqlite_recorder.h"

// clang-format off
#include <httplib.h>  // last: it must follow Eigen (see server/dispatch/dispatch_routes.h)
// clang-format on

namespace dash::http::testing {

namespace {

std::string readText(const std::string& path) {
  std::ifstream in(path);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

log::RunMetadata meta(const std::string& batch, const std::string& params, std::uint64_t seed,
                      const std::string& config, const std::string& settings) {
  return log::RunMetadata{.batch_id = batch,
                          .family = "sorting",
                          .params_json = params,
                          .seed = seed,
                          .planner = "lazy-dash",
                          .planner_settings_json = settings,
                          .planner_config_name = config,
                          .time_limit = 30.0,
                          .code_version = "0.1.0-test",
                          .host = "test-host",
                          .cpu_info = "test cpu"};
}

/// A small stream shaped like Lazy-DaSH's: task elements, a history constraint caused by a
/// conflict, a task space expansion, motion elements, counters and phases over `iterations`.
void emitRun(log::EventEmitter& em, int iterations) {
  using namespace dash::log;
  std::uint32_t v = 0, a = 0;
  {
    PhaseTimer p(em, Phase::TaskConstruction);
    for (int k = 0; k < 6; ++k) em.vertex(Layer::Task, v++, "R" + std::to_string(k % 2) + "+O" + std::to_string(k / 2));
    em.hyperarc(Layer::Task, "pick", a++, {1}, {0}, "pick O0");
  }
  for (int it = 1; it <= iterations; ++it) {
    em.setIteration(it);
    {
      PhaseTimer p(em, Phase::TaskQuery);
      em.vertex(Layer::TaskExtended, static_cast<std::uint32_t>(it), "h" + std::to_string(it));
      em.hyperarc(Layer::TaskExtended, "transition", static_cast<std::uint32_t>(it), {1}, {0});
    }
    {
      PhaseTimer p(em, Phase::TaskConflictDetection);
      em.constraint(ConstraintKind::History, ConstraintAction::Created, static_cast<std::uint32_t>(it),
                    "(v_pre=1, v_post=" + std::to_string(it + 1) + ")", {1, static_cast<std::uint32_t>(it + 1)},
                    "place of O1 collides with O0");
      if (it == 2) em.taskSpaceExpansion(1, "O1", "stable pose 3", "history constraints contradict");
    }
    {
      PhaseTimer p(em, Phase::MotionConstruction);
      em.vertex(Layer::Motion, static_cast<std::uint32_t>(2 * it), "q" + std::to_string(it));
      em.vertex(Layer::Motion, static_cast<std::uint32_t>(2 * it + 1));
      em.hyperarc(Layer::Motion, "move", static_cast<std::uint32_t>(it), {static_cast<std::uint32_t>(2 * it + 1)},
                  {static_cast<std::uint32_t>(2 * it)});
      em.counter("roadmap_vertices", 10 * it);
    }
    {
      PhaseTimer p(em, Phase::MotionQuery);
      em.vertex(Layer::MotionExtended, static_cast<std::uint32_t>(it));
      em.counter("collision_checks_lazy", 7 * it);
    }
  }
}

std::string record(log::ResultsDb& db, const log::RunMetadata& m, int iterations, log::RunSummary summary) {
  const std::string uuid = db.beginRun(m);
  {
    auto recorder = db.recorder(uuid);
    log::EventEmitter em(recorder.get());
    emitRun(em, iterations);
  }
  db.finishRun(uuid, summary);
  return uuid;
}

}  // namespace

Fixture fixtureDb(const std::string& path) {
  log::ResultsDb db(path);
  Fixture f;
  f.batch_id = "fixture-20260101-000000-abcd";
  db.putBatch(log::BatchRecord{.id = f.batch_id, .name = "fixture", .spec_json = "{}", .status = "finished"});
  log::RunSummary solved{.status = log::RunStatus::Solved, .total_time = 1.5, .makespan = 3.38};
  solved.plan_json = readText(std::string(DASHBENCH_EXAMPLES_DIR) + "/pick_place_plan.json");
  f.solved = record(db, meta(f.batch_id, R"({"robots":2,"objects":2})", 1, "lazy-dash", "{}"), 3, solved);
  f.timeout = record(db, meta(f.batch_id, R"({"robots":2,"objects":4})", 1, "lazy-dash", "{}"), 6,
                     log::RunSummary{.status = log::RunStatus::Timeout, .total_time = 30.0});
  f.task_only = record(db, meta(f.batch_id, R"({"robots":2,"objects":2})", 2, "lazy-task", R"({"task_only":true})"), 1,
                       log::RunSummary{.status = log::RunStatus::Solved, .total_time = 0.01});
  return f;
}

ServerOptions testOptions(const std::string& db_path) {
  ServerOptions o;
  o.host = "127.0.0.1";
  o.port = 0;
  o.db_path = db_path;
  o.web_root = std::string(DASHBENCH_SOURCE_DIR) + "/web";
  o.token = kToken;
  o.executable = DASHBENCH_BINARY;
  o.threads = 16;
  o.poll_seconds = 0.1;
  o.max_batch_workers = 2;
  o.max_body_bytes = 64 * 1024;
  return o;
}

std::string Reply::header(const std::string& name) const {
  const auto it = headers.find(name);
  return it == headers.end() ? "" : it->second;
}

namespace {

Reply toReply(const httplib::Result& r) {
  Reply out;
  if (!r) return out;
  out.status = r->status;
  out.body = r->body;
  for (const auto& [k, v] : r->headers) out.headers.emplace(k, v);
  return out;
}

httplib::Headers headersFor(const std::string& token) {
  httplib::Headers h;
  if (!token.empty()) h.emplace("Authorization", "Bearer " + token);
  return h;
}

}  // namespace

Reply Http::get(const std::string& path, const std::string& token) const {
  httplib::Client c("127.0.0.1", port_);
  c.set_read_timeout(30, 0);
  return toReply(c.Get(path, headersFor(token)));
}

Reply Http::post(const std::string& path, const std::string& body, const std::string& token) const {
  httplib::Client c("127.0.0.1", port_);
  c.set_read_timeout(30, 0);
  return toReply(c.Post(path, headersFor(token), body, "application/json"));
}

Reply Http::put(const std::string& path, const std::string& body, const std::string& token) const {
  httplib::Client c("127.0.0.1", port_);
  return toReply(c.Put(path, headersFor(token), body, "application/json"));
}

Reply Http::del(const std::string& path, const std::string& token) const {
  httplib::Client c("127.0.0.1", port_);
  return toReply(c.Delete(path, headersFor(token)));
}

std::string Http::raw(const std::string& request) const {
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(static_cast<std::uint16_t>(port_));
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  std::string out;
  if (connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) == 0) {
    (void)!write(fd, request.data(), request.size());
    timeval tv{.tv_sec = 5, .tv_usec = 0};
    setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
    char buf[4096];
    ssize_t n = 0;
    while ((n = read(fd, buf, sizeof buf)) > 0) out.append(buf, static_cast<std::size_t>(n));
  }
  close(fd);
  return out;
}

bool waitFor(const std::function<bool()>& done, double seconds) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (std::chrono::steady_clock::now() < end) {
    if (done()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return done();
}

std::string tinySpec(const std::string& name, const std::string& objects, const std::string& seeds,
                     const std::string& planner_json, double time_limit) {
  return R"({"name":")" + name + R"(","time_limit":)" + std::to_string(time_limit) +
         R"(,"memory_limit":2048,"scenarios":[{"family":"sorting","params":{"robots":2,"objects":)" + objects +
         R"(}}],"planners":[)" + planner_json + R"(],"seeds":)" + seeds + "}";
}

Json waitForBatch(const Http& http, const std::string& id, const std::string& status, double seconds) {
  Json last;
  waitFor(
      [&] {
        const Reply r = http.get("/api/batches/" + id);
        last = r.json();
        return r.status == 200 && last.value("status", "") == status;
      },
      seconds);
  return last;
}

}  // namespace dash::http::testing
