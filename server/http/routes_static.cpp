// The dashboard's files: GET of anything that is not an API route. Unknown /api/ paths answer a JSON
// 404; paths that try to leave the web root answer 403; the HTML gets a content security policy.
// Every file carries an ETag (its size and modification time) and must be revalidated before reuse
// (Cache-Control: no-cache): a browser that has the file asks with If-None-Match and gets a 304
// without the body, so a reload does not fetch the ~2 MB of JavaScript again (issue 41), and an
// edited file is never served stale.

#include <cinttypes>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "server/http/api_util.h"
#include "server/http/routes.h"

// clang-format off
#include <httplib.h>  // last: it must follow Eigen (see server/dispatch/dispatch_routes.h)
// clang-format on

namespace dash::http {

namespace {

// Scripts only from this server; the one inline script is the import map (Chromium cannot load an
// import map from a file). No frames, no plugins, no other origins.
constexpr const char* kContentSecurityPolicy =
    "default-src 'self'; script-src 'self' 'unsafe-inline'; style-src 'self' 'unsafe-inline'; img-src 'self' data: "
    "blob:; "
    "connect-src 'self'; object-src 'none'; frame-ancestors 'none'; base-uri 'none'; form-action 'self'";

std::string readFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw HttpError(404, "cannot read " + path);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

/// The file's entity tag: "SIZE-MTIME" in hex (nanoseconds), like nginx's; "" if it cannot be read.
std::string entityTag(const std::string& path) {
  std::error_code ec;
  const std::uintmax_t size = std::filesystem::file_size(path, ec);
  if (ec) return "";
  const auto modified = std::filesystem::last_write_time(path, ec);
  if (ec) return "";
  char text[64];
  std::snprintf(text, sizeof text, "\"%" PRIxMAX "-%" PRIx64 "\"", size,
                static_cast<std::uint64_t>(modified.time_since_epoch().count()));
  return text;
}

/// Whether an If-None-Match header names `tag`: "*", or one of its comma-separated tags (a weak
/// W/"..." compares equal, as RFC 9110 asks for If-None-Match).
bool tagMatches(const std::string& header, const std::string& tag) {
  if (tag.empty()) return false;
  std::size_t at = 0;
  while (at < header.size()) {
    std::size_t end = header.find(',', at);
    if (end == std::string::npos) end = header.size();
    std::string item = header.substr(at, end - at);
    item.erase(0, item.find_first_not_of(" \t"));
    item.erase(item.find_last_not_of(" \t") + 1);
    if (item.rfind("W/", 0) == 0) item.erase(0, 2);
    if (item == "*" || item == tag) return true;
    at = end + 1;
  }
  return false;
}

}  // namespace

void registerStaticRoutes(httplib::Server& server, ApiContext& ctx) {
  server.Get(".*", guarded([&ctx](const httplib::Request& req, httplib::Response& res) {
               if (req.path == "/api" || req.path.rfind("/api/", 0) == 0) {
                 throw HttpError(404, "no API route GET " + req.path);
               }
               StaticFile file;
               switch (ctx.files->lookup(req.path, file)) {
                 case StaticLookup::kForbidden:
                   throw HttpError(403, "forbidden path");
                 case StaticLookup::kNotFound:
                   throw HttpError(404, "not found: " + req.path);
                 case StaticLookup::kFound:
                   break;
               }
               // Files change while people work on the dashboard: always revalidated, sent only when changed.
               res.set_header("Cache-Control", "no-cache");
               const std::string tag = entityTag(file.path);
               if (!tag.empty()) res.set_header("ETag", tag);
               if (file.mime_type.rfind("text/html", 0) == 0)
                 res.set_header("Content-Security-Policy", kContentSecurityPolicy);
               if (tagMatches(req.get_header_value("If-None-Match"), tag)) {
                 res.status = 304;
                 return;
               }
               res.set_content(readFile(file.path), file.mime_type.c_str());
             }));
}

}  // namespace dash::http
