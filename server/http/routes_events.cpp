// GET /api/events: server-sent events (text/event-stream) from the EventHub.
//   ?topics=batch,batches,run,sizes   the event names wanted (default: all)
//   ?run=UUID                        only messages about this run (plus batch-list changes)
// A reconnecting EventSource sends Last-Event-ID and gets what it missed while the hub still has
// it; otherwise a "resync" event tells the page to refetch. A comment line every few seconds keeps
// proxies from closing an idle stream and lets the server notice a closed tab.
// Each open stream holds a worker thread: at most ApiContext::max_event_streams are open at once
// (more get 503 with Retry-After), so that streams never take every worker (issue 24).

#include <atomic>
#include <chrono>
#include <memory>
#include <set>

#include "server/http/api_json.h"
#include "server/http/api_util.h"
#include "server/http/routes.h"

// clang-format off
#include <httplib.h>  // last: it must follow Eigen (see server/dispatch/dispatch_routes.h)
// clang-format on

namespace dash::http {

namespace {

constexpr auto kWaitSlice = std::chrono::milliseconds(500);
constexpr auto kKeepAlive = std::chrono::seconds(10);

struct Stream {
  std::uint64_t after = 0;
  std::set<std::string> topics;  ///< empty: every event
  std::string run;
  bool hello_sent = false;
  std::chrono::steady_clock::time_point last_write = std::chrono::steady_clock::now();
};

bool wanted(const Stream& s, const HubMessage& m) {
  if (!s.topics.empty() && s.topics.count(m.event) == 0) return false;
  if (!s.run.empty() && (m.event == "run" || m.event == "sizes") && m.key != s.run) return false;
  return true;
}

/// Writes what the stream has not sent yet (or a keep-alive); false when the client is gone.
bool nextFrames(Stream& stream, const EventHub& hub, httplib::DataSink& sink) {
  auto write = [&](const std::string& text) {
    stream.last_write = std::chrono::steady_clock::now();
    return sink.write(text.data(), text.size());
  };
  if (!stream.hello_sent) {
    stream.hello_sent = true;
    return write("retry: 2000\nevent: hello\ndata: " + jsonText(Json{{"seq", stream.after}}) + "\n\n");
  }
  if (!sink.is_writable()) return false;  // the tab was closed: free the worker now
  const HubWait w = hub.waitAfter(stream.after, kWaitSlice);
  if (w.closed) {
    sink.done();
    return true;
  }
  std::string out;
  if (w.gap) out += "event: resync\ndata: {}\n\n";
  for (const HubMessage& m : w.messages) {
    stream.after = m.seq;
    if (wanted(stream, m)) out += EventHub::formatSse(m);
  }
  if (out.empty()) {
    if (std::chrono::steady_clock::now() - stream.last_write < kKeepAlive) return true;
    out = ": keep-alive\n\n";
  }
  return write(out);
}

}  // namespace

void registerEventRoutes(httplib::Server& server, ApiContext& ctx) {
  auto open_streams = std::make_shared<std::atomic<int>>(0);
  server.Get("/api/events", guarded([&ctx, open_streams](const httplib::Request& req, httplib::Response& res) {
               if (open_streams->fetch_add(1) >= ctx.max_event_streams) {
                 open_streams->fetch_sub(1);
                 res.set_header("Retry-After", "5");
                 throw HttpError(503, "too many open event streams (" + std::to_string(ctx.max_event_streams) +
                                          "); close a dashboard tab or try again later");
               }
               // Counted from here; the releaser below uncounts it when the response is gone.
               const std::shared_ptr<void> counted(nullptr, [open_streams](void*) { open_streams->fetch_sub(1); });
               auto stream = std::make_shared<Stream>();
               stream->after = ctx.hub->lastSeq();
               if (req.has_header("Last-Event-ID")) {
                 try {
                   const std::uint64_t id = std::stoull(req.get_header_value("Last-Event-ID"));
                   if (id <= stream->after) stream->after = id;
                 } catch (const std::exception&) {
                   // A malformed id: start from now.
                 }
               }
               const std::string topics = param(req, "topics");
               std::size_t start = 0;
               while (start < topics.size()) {
                 const std::size_t comma = topics.find(',', start);
                 const std::string t =
                     topics.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
                 if (!t.empty()) stream->topics.insert(t);
                 if (comma == std::string::npos) break;
                 start = comma + 1;
               }
               stream->run = param(req, "run");
               res.set_header("Cache-Control", "no-cache");
               res.set_header("X-Accel-Buffering", "no");
               EventHub* hub = ctx.hub;
               // The provider runs after the handler returned, outside guarded(): it must not throw.
               res.set_chunked_content_provider(
                   "text/event-stream",
                   [stream, hub](std::size_t, httplib::DataSink& sink) {
                     try {
                       return nextFrames(*stream, *hub, sink);
                     } catch (const std::exception&) {
                       return false;  // ends this stream only
                     }
                   },
                   [counted](bool) {});
             }));
}

}  // namespace dash::http
