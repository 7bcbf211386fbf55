#include "server/http/api_util.h"

#include <cstdio>
#include <exception>
#include <limits>

#include "engine/core/check.h"
#include "engine/log/sqlite_util.h"
#include "server/http/api_json.h"
#include "server/http/json_depth.h"

// clang-format off
#include <httplib.h>  // last: it must follow Eigen (see server/dispatch/dispatch_routes.h)
// clang-format on

// httplib after every project header: it pulls in <resolv.h>, whose `_res` macro breaks Eigen.

namespace dash::http {

std::string errorJson(const std::string& message) { return jsonText(Json{{"error", message}}); }

void replyJson(httplib::Response& res, int status, const std::string& json_text) {
  res.status = status;
  res.set_content(json_text, kJsonType);
}

void replyError(httplib::Response& res, int status, const std::string& message) {
  replyJson(res, status, errorJson(message));
}

ConcurrencySlot::ConcurrencySlot(std::atomic<int>& running, int cap, const std::string& message) : running_(running) {
  if (running_.fetch_add(1) >= cap) {
    running_.fetch_sub(1);
    throw HttpError(503, message, 1);
  }
}

ConcurrencySlot::~ConcurrencySlot() { running_.fetch_sub(1); }

bool constantTimeEquals(std::string_view a, std::string_view b) {
  // The length is not secret (tokens have a fixed format); the content is compared in full.
  unsigned char diff = a.size() == b.size() ? 0 : 1;
  const std::size_t n = std::min(a.size(), b.size());
  for (std::size_t i = 0; i < n; ++i) diff |= static_cast<unsigned char>(a[i] ^ b[i]);
  return diff == 0;
}

bool hasToken(const httplib::Request& req, const std::string& token) {
  if (token.empty() || !req.has_header("Authorization")) return false;
  const std::string value = req.get_header_value("Authorization");
  constexpr std::string_view kBearer = "Bearer ";
  if (value.size() <= kBearer.size() || value.compare(0, kBearer.size(), kBearer) != 0) return false;
  return constantTimeEquals(std::string_view(value).substr(kBearer.size()), token);
}

void requireToken(const httplib::Request& req, const std::string& token) {
  if (!req.has_header("Authorization")) {
    throw HttpError(401,
                    "this request changes something and needs the server's token: send the header "
                    "'Authorization: Bearer TOKEN' (the token is in the server's token file)");
  }
  if (!hasToken(req, token)) throw HttpError(401, "wrong token in the Authorization header");
}

std::string param(const httplib::Request& req, const std::string& name, const std::string& fallback) {
  return req.has_param(name.c_str()) ? req.get_param_value(name.c_str()) : fallback;
}

std::int64_t intParam(const httplib::Request& req, const std::string& name, std::int64_t fallback, std::int64_t min,
                      std::int64_t max) {
  if (!req.has_param(name.c_str())) return fallback;
  const std::string text = req.get_param_value(name.c_str());
  std::int64_t value = 0;
  std::size_t used = 0;
  try {
    value = std::stoll(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != text.size())
    throw HttpError(400, "parameter '" + name + "': '" + text + "' is not an integer");
  if (value < min || value > max) {
    throw HttpError(400, "parameter '" + name + "': " + text + " is out of range " + std::to_string(min) + ".." +
                             std::to_string(max));
  }
  return value;
}

Handler guarded(Handler handler) {
  return [handler = std::move(handler)](const httplib::Request& req, httplib::Response& res) {
    try {
      handler(req, res);
    } catch (const HttpError& e) {
      replyError(res, e.status(), e.what());
      if (e.retryAfter() > 0) res.set_header("Retry-After", std::to_string(e.retryAfter()));
    } catch (const InputError& e) {
      replyError(res, 400, e.what());
    } catch (const log::DbError& e) {
      // SQLite's message quotes the SQL and the file's path: for the server's log, not for clients.
      const std::string what = e.what();
      std::fprintf(stderr, "dashbench serve: %s %s: %s\n", req.method.c_str(), req.path.c_str(), what.c_str());
      if (what.find("database is locked") != std::string::npos || what.find("database is busy") != std::string::npos) {
        replyError(res, 503, "the results database is busy; try again in a moment");
        res.set_header("Retry-After", "1");
      } else {
        replyError(res, 503, "results database error (the server's log has the details)");
      }
    } catch (const std::exception& e) {
      std::fprintf(stderr, "dashbench serve: %s %s failed: %s\n", req.method.c_str(), req.path.c_str(), e.what());
      replyError(res, 500, std::string("internal error: ") + e.what());
    }
  };
}

std::string jsonText(const Json& j) { return j.dump(-1, ' ', false, Json::error_handler_t::replace); }

Json parseBodyObject(const httplib::Request& req) {
  if (req.body.empty()) throw HttpError(400, "the request body is empty; expected a JSON object");
  if (jsonTooDeep(req.body)) {
    throw HttpError(400, "the request body nests deeper than " + std::to_string(kMaxJsonDepth) + " levels");
  }
  Json j;
  try {
    j = Json::parse(req.body);
  } catch (const Json::exception& e) {
    // parse_error, and out_of_range for numbers such as 1e400
    throw HttpError(400, std::string("the request body is not valid JSON: ") + e.what());
  }
  if (!j.is_object()) throw HttpError(400, "the request body must be a JSON object");
  return j;
}

std::int64_t intMember(const Json& body, const std::string& key, std::int64_t min, std::int64_t max) {
  const Json& v = body.at(key);
  bool ok = v.is_number_integer();
  std::int64_t value = 0;
  if (v.is_number_unsigned()) {
    const auto u = v.get<std::uint64_t>();
    ok = u <= static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max());
    value = static_cast<std::int64_t>(u);
  } else if (ok) {
    value = v.get<std::int64_t>();
  }
  if (!ok || value < min || value > max) {
    throw HttpError(400, key + ": expected an integer in " + std::to_string(min) + ".." + std::to_string(max));
  }
  return value;
}

Json toJson(const log::SqlValue& value) {
  return std::visit(
      [](const auto& v) -> Json {
        using T = std::decay_t<decltype(v)>;
        if constexpr (std::is_same_v<T, std::monostate>) {
          return nullptr;
        } else {
          return v;
        }
      },
      value);
}

Json rowsToJson(const log::SqlRows& rows) {
  Json out = {{"columns", rows.columns}, {"rows", Json::array()}, {"truncated", rows.truncated}};
  for (const auto& row : rows.rows) {
    Json r = Json::array();
    for (const auto& v : row) r.push_back(toJson(v));
    out["rows"].push_back(std::move(r));
  }
  return out;
}

Json rowObject(const log::SqlRows& rows, std::size_t i) {
  Json out = Json::object();
  for (std::size_t c = 0; c < rows.columns.size(); ++c) out[rows.columns[c]] = toJson(rows.rows[i][c]);
  return out;
}

Json parseStored(const std::string& text) {
  if (text.empty()) return nullptr;
  Json j = Json::parse(text, nullptr, false);
  return j.is_discarded() ? Json(nullptr) : j;
}

}  // namespace dash::http
