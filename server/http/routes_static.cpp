// The dashboard's files: GET of anything that is not an API route. Unknown /api/ paths answer a JSON
// 404; paths that try to leave the web root answer 403; the HTML gets a content security policy.

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
               res.set_content(readFile(file.path), file.mime_type.c_str());
               if (file.mime_type.rfind("text/html", 0) == 0)
                 res.set_header("Content-Security-Policy", kContentSecurityPolicy);
               // Files change while people work on the dashboard; revalidation is cheap on loopback.
               res.set_header("Cache-Control", "no-cache");
             }));
}

}  // namespace dash::http
