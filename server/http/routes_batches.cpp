// /api/batches: validate a spec, submit it, list batches, inspect one, cancel, resume.

#include <atomic>
#include <memory>

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
constexpr std::int64_t kMaxWorkers = 1024;          ///< runs at once (the server caps it further by its cores)
constexpr std::int64_t kMaxSlurmParallel = 100000;  ///< a Slurm array's %N throttle; 0: none
constexpr int kMaxConcurrentValidations = 2;        ///< spec validations at once (token-free, CPU-bound)

struct Submission {
  std::string spec_json;
  int workers = 1;
  std::string backend = "local";  ///< "local" or "slurm"
  SlurmRequest slurm;
};

/// {"partition": "P", "account": "A", "max_parallel": N}, each optional.
SlurmRequest slurmRequestOf(const Json& j) {
  if (!j.is_object()) throw HttpError(400, "slurm: expected a JSON object");
  SlurmRequest r;
  for (const auto& [key, value] : j.items()) {
    if (key == "partition" || key == "account") {
      if (!value.is_string()) throw HttpError(400, "slurm." + key + ": expected a string");
      (key == "partition" ? r.partition : r.account) = value.get<std::string>();
    } else if (key == "max_parallel") {
      r.max_parallel = static_cast<int>(intMember(j, "max_parallel", 0, kMaxSlurmParallel));
    } else {
      throw HttpError(400, "slurm: unknown key '" + key + "' (expected partition, account, max_parallel)");
    }
  }
  return r;
}

/// The body is the spec itself (as for `dashbench batch run`), or {"spec": {...}, "workers": N,
/// "backend": "local"|"slurm", "slurm": {...}}.
Submission submissionOf(const httplib::Request& req) {
  const Json body = parseBodyObject(req);
  Submission s;
  s.workers = static_cast<int>(intParam(req, "workers", 1, 1, kMaxWorkers));
  if (body.contains("spec") && !body.contains("scenarios")) {
    const Json& spec = body["spec"];
    if (!spec.is_object()) throw HttpError(400, "spec: expected a JSON object (a batch spec)");
    s.spec_json = jsonText(spec);
    if (body.contains("workers")) {
      s.workers = static_cast<int>(intMember(body, "workers", 1, kMaxWorkers));
    }
    if (body.contains("backend")) {
      if (!body["backend"].is_string()) throw HttpError(400, "backend: expected \"local\" or \"slurm\"");
      s.backend = body["backend"].get<std::string>();
      if (s.backend != "local" && s.backend != "slurm")
        throw HttpError(400, "backend: expected \"local\" or \"slurm\"");
    }
    if (body.contains("slurm")) s.slurm = slurmRequestOf(body["slurm"]);
    for (const auto& [key, value] : body.items()) {
      if (key != "spec" && key != "workers" && key != "backend" && key != "slurm") {
        throw HttpError(400, "unknown key '" + key + "' (expected spec, workers, backend, slurm)");
      }
    }
  } else {
    s.spec_json = jsonText(body);
  }
  return s;
}

/// SpecError carries which rule was broken: the page shows it next to the field.
void replySpecError(httplib::Response& res, const batch::SpecError& e) {
  replyJson(res, 400, jsonText(Json{{"error", e.what()}, {"kind", batch::toString(e.kind())}}));
}

}  // namespace

void registerBatchRoutes(httplib::Server& server, ApiContext& ctx) {
  // Checking is what this request is for: a spec that breaks a rule is a 200 answer {"valid": false,
  // "error", "kind"} (the Launch page asks on every keystroke); a body that is not JSON is still a 400.
  // Token-free and CPU-bound (a 3,968-combination grid costs 1.8 s of generator probes): capped, so
  // that clients asking at once cannot take every core; more get 503 with Retry-After (issue 40).
  auto validating = std::make_shared<std::atomic<int>>(0);
  server.Post("/api/batches/validate", guarded([&ctx, validating](const httplib::Request& req, httplib::Response& res) {
                const Submission s = submissionOf(req);
                const ConcurrencySlot slot(*validating, kMaxConcurrentValidations,
                                           "too many spec validations at once; try again in a moment");
                try {
                  Json out = Json::parse(ctx.batches->validateJson(s.spec_json, kPreviewKeys));
                  out["valid"] = true;
                  replyJson(res, 200, jsonText(out));
                } catch (const batch::SpecError& e) {
                  replyJson(res, 200,
                            jsonText(Json{{"valid", false}, {"error", e.what()}, {"kind", batch::toString(e.kind())}}));
                }
              }));

  server.Post(
      "/api/batches", guarded([&ctx](const httplib::Request& req, httplib::Response& res) {
        requireToken(req, ctx.token);
        const Submission s = submissionOf(req);
        try {
          const SubmitOutcome out = s.backend == "slurm" ? ctx.batches->submitSlurm(s.spec_json, s.slurm)
                                                         : ctx.batches->submit(s.spec_json, s.workers);
          replyJson(res, 202, jsonText(Json{{"batch_id", out.batch_id}, {"runs", out.runs}, {"status", out.status}}));
        } catch (const batch::SpecError& e) {
          replySpecError(res, e);
        } catch (const InputError& e) {
          if (s.backend != "slurm") throw;
          replyJson(res, 400, jsonText(Json{{"error", std::string("backend: ") + e.what()}}));  // sbatch refused it
        }
      }));

  // The backends this server offers: "slurm" only where sbatch is on its PATH.
  server.Get("/api/batches/backends", guarded([&ctx](const httplib::Request&, httplib::Response& res) {
               Json backends = Json::array({"local"});
               if (ctx.batches->slurmAvailable()) backends.push_back("slurm");
               replyJson(res, 200, jsonText(Json{{"backends", backends}}));
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
                replyJson(res, 202, jsonText(Json{{"batch_id", id}, {"cancelling", true}}));
              }));

  server.Post(std::string(kBatchId) + "/resume", guarded([&ctx](const httplib::Request& req, httplib::Response& res) {
                requireToken(req, ctx.token);
                const std::string id = req.matches[1];
                int workers = static_cast<int>(intParam(req, "workers", 1, 1, kMaxWorkers));
                if (!req.body.empty()) {
                  const Json body = parseBodyObject(req);
                  if (body.contains("workers")) {
                    workers = static_cast<int>(intMember(body, "workers", 1, kMaxWorkers));
                  }
                }
                ctx.batches->resume(id, workers);
                replyJson(res, 202, jsonText(Json{{"batch_id", id}, {"status", "queued"}}));
              }));
}

}  // namespace dash::http
