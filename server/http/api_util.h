#pragma once
// What every route of the HTTP API shares: JSON replies, errors as {"error": "..."}, the token check,
// query parameters, and the wrapper that turns any exception of a handler into a JSON answer.
// httplib stays out of this header (it must be included after Eigen; see dispatch_routes.h).
#include <atomic>
#include <cstdint>
#include <functional>
#include <stdexcept>
#include <string>
#include <string_view>

namespace httplib {
struct Request;
struct Response;
}  // namespace httplib

namespace dash::http {

/// A request the API refuses, with its HTTP status (4xx) and a message for people.
class HttpError : public std::runtime_error {
 public:
  HttpError(int status, const std::string& message, int retry_after_seconds = 0)
      : std::runtime_error(message), status_(status), retry_after_(retry_after_seconds) {}
  int status() const { return status_; }
  /// Sent as Retry-After when positive (a 503 of a capped route).
  int retryAfter() const { return retry_after_; }

 private:
  int status_;
  int retry_after_;
};

/// Counts the requests of a capped route running at once; one more than `cap` is an HttpError 503
/// with Retry-After: 1 and `message`. Held for the request's lifetime.
class ConcurrencySlot {
 public:
  ConcurrencySlot(std::atomic<int>& running, int cap, const std::string& message);
  ~ConcurrencySlot();
  ConcurrencySlot(const ConcurrencySlot&) = delete;
  ConcurrencySlot& operator=(const ConcurrencySlot&) = delete;

 private:
  std::atomic<int>& running_;
};

inline constexpr const char* kJsonType = "application/json";

/// {"error": message} as JSON text.
std::string errorJson(const std::string& message);
void replyJson(httplib::Response& res, int status, const std::string& json_text);
void replyError(httplib::Response& res, int status, const std::string& message);

/// Compares in time independent of where the strings differ (the token check).
bool constantTimeEquals(std::string_view a, std::string_view b);
/// True when the request carries `Authorization: Bearer <token>` with this token.
bool hasToken(const httplib::Request& req, const std::string& token);
/// Throws HttpError 401 unless hasToken().
void requireToken(const httplib::Request& req, const std::string& token);

/// A query parameter, or `fallback` when absent.
std::string param(const httplib::Request& req, const std::string& name, const std::string& fallback = "");
/// An integer query parameter within [min, max]; HttpError 400 naming it otherwise.
std::int64_t intParam(const httplib::Request& req, const std::string& name, std::int64_t fallback, std::int64_t min,
                      std::int64_t max);

using Handler = std::function<void(const httplib::Request&, httplib::Response&)>;
/// Runs `handler`, answering HttpError with its status, InputError with 400, a database error with
/// 503 and anything else with 500, each as {"error": ...}. A handler never takes the server down.
Handler guarded(Handler handler);

}  // namespace dash::http
