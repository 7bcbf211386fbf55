// http_load: N clients (each its own kept-alive connection) GET one path of a dashbench server on
// 127.0.0.1 as fast as they can for a fixed time; prints requests per second, latency percentiles,
// errors, and the server's resident memory (VmRSS of --pid, sampled every 20 ms) before and at peak.
//
//   build/http_load --port 8080 --path /api/runs --clients 32 --seconds 10 --pid $(pgrep -n dashbench)
//
// Loopback only by construction (the host is not an option); bounded by --seconds.
#include <httplib.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace {

using Clock = std::chrono::steady_clock;

struct Options {
  int port = 8080;
  std::string path = "/api/runs";
  int clients = 32;
  double seconds = 10;
  long pid = 0;
};

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string key = argv[i];
    const char* value = argv[i + 1];
    if (key == "--port") {
      o.port = std::atoi(value);
    } else if (key == "--path") {
      o.path = value;
    } else if (key == "--clients") {
      o.clients = std::atoi(value);
    } else if (key == "--seconds") {
      o.seconds = std::atof(value);
    } else if (key == "--pid") {
      o.pid = std::atol(value);
    } else {
      std::fprintf(stderr, "unknown option %s\n", key.c_str());
      std::exit(2);
    }
  }
  if (o.clients < 1 || o.clients > 1024 || o.seconds <= 0 || o.seconds > 600 || o.port <= 0) {
    std::fprintf(stderr,
                 "usage: http_load --port P [--path /api/runs] [--clients 1..1024] [--seconds 0..600] [--pid PID]\n");
    std::exit(2);
  }
  return o;
}

/// VmRSS of `pid` in kB; 0 if unknown.
long rssKb(long pid) {
  if (pid <= 0) return 0;
  std::ifstream in("/proc/" + std::to_string(pid) + "/status");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("VmRSS:", 0) == 0) return std::atol(line.c_str() + 6);
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  const Options o = parse(argc, argv);
  const long rss_before = rssKb(o.pid);
  std::atomic<bool> stop{false};
  std::atomic<long> rss_peak{rss_before};
  std::thread sampler([&] {
    while (!stop) {
      const long r = rssKb(o.pid);
      long seen = rss_peak.load();
      while (r > seen && !rss_peak.compare_exchange_weak(seen, r)) {
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
  });

  std::mutex mutex;
  std::vector<double> latencies_ms;
  long errors = 0;
  long bytes = 0;
  const auto end = Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(o.seconds));
  const auto start = Clock::now();
  std::vector<std::thread> clients;
  for (int i = 0; i < o.clients; ++i) {
    clients.emplace_back([&] {
      httplib::Client client("127.0.0.1", o.port);
      client.set_keep_alive(true);
      client.set_tcp_nodelay(true);
      client.set_read_timeout(30, 0);
      std::vector<double> mine;
      long my_errors = 0;
      long my_bytes = 0;
      while (Clock::now() < end) {
        const auto t0 = Clock::now();
        const httplib::Result r = client.Get(o.path);
        const auto t1 = Clock::now();
        if (!r || r->status != 200) {
          ++my_errors;
          continue;
        }
        my_bytes += static_cast<long>(r->body.size());
        mine.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
      }
      std::lock_guard lock(mutex);
      latencies_ms.insert(latencies_ms.end(), mine.begin(), mine.end());
      errors += my_errors;
      bytes += my_bytes;
    });
  }
  for (auto& t : clients) t.join();
  const double elapsed = std::chrono::duration<double>(Clock::now() - start).count();
  stop = true;
  sampler.join();

  std::sort(latencies_ms.begin(), latencies_ms.end());
  auto pct = [&](double p) {
    return latencies_ms.empty() ? 0.0 : latencies_ms[static_cast<std::size_t>(p * (latencies_ms.size() - 1))];
  };
  std::printf("path %s, %d clients, %.1f s: %zu ok, %ld errors, %.0f requests/s, %.1f MB/s\n", o.path.c_str(),
              o.clients, elapsed, latencies_ms.size(), errors, latencies_ms.size() / elapsed, bytes / elapsed / 1e6);
  std::printf("latency ms: p50 %.2f, p90 %.2f, p99 %.2f, max %.2f\n", pct(0.5), pct(0.9), pct(0.99), pct(1.0));
  if (o.pid > 0) std::printf("server RSS: %.1f MB before, %.1f MB peak\n", rss_before / 1024.0, rss_peak / 1024.0);
  return errors == 0 ? 0 : 1;
}
