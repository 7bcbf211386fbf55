// /api/batches: validate a spec, submit it, list batches, inspect one, cancel, resume.

#include "server/batch/batch_spec.h"
#include "server/http/api_json.h"
#include "server/http/api_util.h"
#include "server/http/routes.h"

// clang-format off
#include <httplib.h>  // last: it must follow Eigen (see server/dispatch/dispatch_routes.h)
// clang-format on

namespace dash::http {

namespace {

constexpr const char* kBatchId = R"(/api/batches/([A-Za-z0-9_.\-]+))";
constexpr std::size_t kPreviewKeys = 200;

struct Submission {
  std::string spec_json;
  int workers = 1;
};

/// The body is the spec itself (as for `dashbench batch run`), or {"spec": {...}, "workers": N}.
Submission submissionOf(const httplib::Request& req) {
  const Json body = parseBodyObject(req);
  Submission s;
  s.workers = static_cast<int>(intParam(req, "workers", 1, 1, 1024));
  if (body.contains("spec") && !body.contains("scenarios")) {
    const Json& spec = body["spec"];
    if (!spec.is_object()) throw HttpError(400, "spec: expected a JSON object (a batch spec)");
    s.spec_json = spec.dump();
    if (body.contains("workers")) {
      if (!body["workers"].is_number_integer()) throw HttpError(400, "workers: expected an integer");
      s.workers = body["workers"].get<int>();
    }
    for (const auto& [key, value] : body.items()) {
      if (key != "spec" && key != "workers") throw HttpError(400, "unknown key '" + key + "' (expected spec, workers)");
    }
  } else {
    s.spec_json = body.dump();
  }
  return s;
}

/// SpecError carries which rule was broken: the page shows it next to the field.
void replySpecError(httplib::Response& res, const batch::SpecError& e) {
  replyJson(res, 400, Json{{"error", e.what()}, {"kind", batch::toString(e.kind())}}.dump());
}

}  // namespace

void registerBatchRoutes(httplib::Server& server, ApiContext& ctx) {
  // Checking is what this request is for: a spec that breaks a rule is a 200 answer {"valid": false,
  // "error", "kind"} (the Launch page asks on every keystroke); a body that is not JSON is still a 400.
  server.Post(
      "/api/batches/validate", guarded([&ctx](const httplib::Request& req, httplib::Response& res) {
        const Submission s = submissionOf(req);
        try {
          Json out = Json::parse(ctx.batches->validateJson(s.spec_json, kPreviewKeys));
          out["valid"] = true;
          replyJson(res, 200, out.dump());
        } catch (const batch::SpecError& e) {
          replyJson(res, 200, Json{{"valid", false}, {"error", e.what()}, {"kind", batch::toString(e.kind())}}.dump());
        }
      }));

  server.Post(
      "/api/batches", guarded([&ctx](const httplib::Request& req, httplib::Response& res) {
        requireToken(req, ctx.token);
        const Submission s = submissionOf(req);
        try {
          const SubmitOutcome out = ctx.batches->submit(s.spec_json, s.workers);
          replyJson(res, 202, Json{{"batch_id", out.batch_id}, {"runs", out.runs}, {"status", out.status}}.dump());
        } catch (const batch::SpecError& e) {
          replySpecError(res, e);
        }
      }));

  server.Get("/api/batches", guarded([&ctx](const httplib::Request&, httplib::Response& res) {
               replyJson(res, 200, ctx.batches->batchesJson());
             }));

  server.Get(kBatchId, guarded([&ctx](const httplib::Request& req, httplib::Response& res) {
               replyJson(res, 200, ctx.batches->batchJson(req.matches[1]));
             }));

  server.Post(std::string(kBatchId) + "/cancel", guarded([&ctx](const httplib::Request& req, httplib::Response& res) {
                requireToken(req, ctx.token);
                const std::string id = req.matches[1];
                ctx.batches->cancel(id);
                replyJson(res, 202, Json{{"batch_id", id}, {"cancelling", true}}.dump());
              }));

  server.Post(std::string(kBatchId) + "/resume", guarded([&ctx](const httplib::Request& req, httplib::Response& res) {
                requireToken(req, ctx.token);
                const std::string id = req.matches[1];
                int workers = static_cast<int>(intParam(req, "workers", 1, 1, 1024));
                if (!req.body.empty()) {
                  const Json body = parseBodyObject(req);
                  if (body.contains("workers")) {
                    if (!body["workers"].is_number_integer()) throw HttpError(400, "workers: expected an integer");
                    workers = body["workers"].get<int>();
                  }
                }
                ctx.batches->resume(id, workers);
                replyJson(res, 202, Json{{"batch_id", id}, {"status", "queued"}}.dump());
              }));
}

}  // namespace dash::http
