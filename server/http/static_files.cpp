#include "server/http/static_files.h"

#include <filesystem>
#include <system_error>

namespace dash::http {

namespace fs = std::filesystem;

namespace {

/// Splits "/a/b/c" into segments; false when a segment could climb out or hide something.
bool safeSegments(const std::string& url_path, std::vector<std::string>& segments) {
  if (url_path.empty() || url_path[0] != '/') return false;
  if (url_path.find('\\') != std::string::npos || url_path.find('\0') != std::string::npos) return false;
  std::size_t start = 1;
  while (start <= url_path.size()) {
    const std::size_t slash = url_path.find('/', start);
    const std::string seg = url_path.substr(start, slash == std::string::npos ? std::string::npos : slash - start);
    if (slash == std::string::npos && seg.empty() && !segments.empty()) return false;  // trailing slash
    if (seg.empty() && slash != std::string::npos) return false;                       // "//"
    if (!seg.empty()) {
      if (seg == "." || seg == ".." || seg[0] == '.') return false;
      segments.push_back(seg);
    }
    if (slash == std::string::npos) break;
    start = slash + 1;
  }
  return true;
}

bool within(const fs::path& root, const fs::path& p) {
  const std::string r = root.string();
  const std::string s = p.string();
  return s.size() > r.size() && s.compare(0, r.size(), r) == 0 && s[r.size()] == '/';
}

}  // namespace

StaticFiles::StaticFiles(const std::string& web_root) {
  std::error_code ec;
  fs::path p = fs::weakly_canonical(fs::absolute(web_root), ec);
  root_ = ec ? fs::absolute(web_root).lexically_normal().string() : p.string();
  while (root_.size() > 1 && root_.back() == '/') root_.pop_back();
}

const std::vector<VendorFile>& StaticFiles::vendorFiles() {
  // Each entry mirrors the package's own folder layout where its modules import each other by
  // relative path (chart.js/chunks, three.core.js); the import map in index.html names the rest.
  static const std::vector<VendorFile> files = {
      {"/vendor/chart.js/chart.js", "chart.js/dist/chart.js"},
      {"/vendor/chart.js/helpers.js", "chart.js/dist/helpers.js"},
      {"/vendor/chart.js/chunks/index.js", "chart.js/dist/chunks/index.js"},
      {"/vendor/kurkle-color.js", "@kurkle/color/dist/color.esm.js"},
      {"/vendor/boxplots.js", "@sgratzl/boxplots/build/index.js"},
      {"/vendor/chartjs-chart-boxplot.js", "@sgratzl/chartjs-chart-boxplot/build/index.js"},
      {"/vendor/three/three.module.js", "three/build/three.module.js"},
      {"/vendor/three/three.core.js", "three/build/three.core.js"},
      {"/vendor/three/OrbitControls.js", "three/examples/jsm/controls/OrbitControls.js"},
  };
  return files;
}

std::string StaticFiles::mimeTypeOf(const std::string& path) {
  const std::string ext = fs::path(path).extension().string();
  if (ext == ".html") return "text/html; charset=utf-8";
  if (ext == ".js" || ext == ".mjs") return "text/javascript; charset=utf-8";
  if (ext == ".css") return "text/css; charset=utf-8";
  if (ext == ".svg") return "image/svg+xml";
  if (ext == ".png") return "image/png";
  if (ext == ".ico") return "image/x-icon";
  return "";
}

StaticLookup StaticFiles::lookup(const std::string& url_path, StaticFile& out) const {
  std::vector<std::string> segments;
  if (!safeSegments(url_path, segments)) return StaticLookup::kForbidden;
  if (segments.empty()) return resolve("index.html", out);
  if (segments[0] == "vendor") {
    for (const VendorFile& v : vendorFiles()) {
      if (url_path == v.url) return resolve(std::string("node_modules/") + v.file, out);
    }
    return StaticLookup::kNotFound;
  }
  if (segments[0] == "node_modules") return StaticLookup::kForbidden;
  std::string relative;
  for (const std::string& s : segments) relative += (relative.empty() ? "" : "/") + s;
  return resolve(relative, out);
}

StaticLookup StaticFiles::resolve(const std::string& relative, StaticFile& out) const {
  const std::string mime = mimeTypeOf(relative);
  if (mime.empty()) return StaticLookup::kNotFound;
  std::error_code ec;
  const fs::path full = fs::path(root_) / relative;
  const fs::path real = fs::canonical(full, ec);  // follows symbolic links: they must stay inside too
  if (ec) return StaticLookup::kNotFound;
  if (!within(fs::path(root_), real)) return StaticLookup::kForbidden;
  if (!fs::is_regular_file(real, ec)) return StaticLookup::kNotFound;
  out.path = real.string();
  out.mime_type = mime;
  return StaticLookup::kFound;
}

}  // namespace dash::http
