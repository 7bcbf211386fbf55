// GET /api/events: server-sent events (text/event-stream) from the EventHub.
//   ?topics=batch,batches,run,sizes   the event names wanted (default: all)
//   ?run=UUID                        only messages about this run (plus batch-list changes)
// A reconnecting EventSource sends Last-Event-ID and gets what it missed while the hub still has
// it; otherwise a "resync" event tells the page to refetch. A comment line every few seconds keeps
// proxies from closing an idle stream and lets the server notice a closed tab.
// Each open stream holds a worker thread: at most ApiContext::max_event_streams are open at once, so
// that streams never take every worker (issue 24). A new stream beyond that ends the oldest one (it
// closes within kWaitSlice; its EventSource reconnects), so that streams nobody reads cannot keep
// real tabs out. Only while more than half that many dropped streams are still closing does a new
// one get 503 with Retry-After: streams never hold more than 1.5 x the cap of workers.

#include <atomic>
#include <chrono>
#include <list>
#include <memory>
#include <mutex>
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
  std::atomic<bool> dropped{false};  ///< ended by a newer stream: close at the next frame
};

/// The open streams, oldest first, and the dropped ones not yet closed.
class StreamRegistry {
 public:
  /// Registers `s`, dropping the oldest stream when `cap` are open. False (nothing registered) when
  /// too many dropped ones are still closing.
  bool open(const std::shared_ptr<Stream>& s, std::size_t cap) {
    std::lock_guard lock(mutex_);
    if (open_.size() >= cap) {
      if (closing_ >= std::max<std::size_t>(1, cap / 2)) return false;
      open_.front()->dropped = true;
      open_.pop_front();
      ++closing_;
    }
    open_.push_back(s);
    return true;
  }
  void close(const std::shared_ptr<Stream>& s) {
    std::lock_guard lock(mutex_);
    if (s->dropped) {
      --closing_;
    } else {
      open_.remove(s);
    }
  }

 private:
  std::mutex mutex_;
  std::list<std::shared_ptr<Stream>> open_;
  std::size_t closing_ = 0;
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
  if (stream.dropped) return false;       // a newer stream took its place
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
  auto registry = std::make_shared<StreamRegistry>();
  server.Get("/api/events", guarded([&ctx, registry](const httplib::Request& req, httplib::Response& res) {
               auto stream = std::make_shared<Stream>();
               if (!registry->open(stream, static_cast<std::size_t>(ctx.max_event_streams))) {
                 res.set_header("Retry-After", "1");
                 throw HttpError(503, "too many event streams opened at once; try again in a moment");
               }
               // Registered from here; the releaser below unregisters it when the response is gone.
               const std::shared_ptr<void> counted(nullptr, [registry, stream](void*) { registry->close(stream); });
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
