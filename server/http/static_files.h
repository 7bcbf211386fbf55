#pragma once
// The dashboard's static files: everything under the web root with a known extension, plus the npm
// files the dashboard imports, served from web/node_modules through an explicit allow-list under
// /vendor/ (no CDN, no bundler at run time). A URL can never reach a file outside those: paths with
// "..", ".", empty or hidden segments, backslashes or NUL are refused, node_modules is reachable only
// through the allow-list, and the resolved path (symbolic links followed) must stay in the web root.
#include <string>
#include <vector>

namespace dash::http {

enum class StaticLookup { kFound, kNotFound, kForbidden };

struct StaticFile {
  std::string path;       ///< on disk
  std::string mime_type;  ///< with charset for text
};

/// One allow-listed npm file: URL path (under /vendor/) -> file under web/node_modules/.
struct VendorFile {
  const char* url;
  const char* file;
};

class StaticFiles {
 public:
  /// `web_root`: the folder holding index.html (made absolute).
  explicit StaticFiles(const std::string& web_root);

  const std::string& root() const { return root_; }
  /// Maps a percent-decoded URL path ("/", "/js/app.js", "/vendor/chart.js/chart.js") to a file.
  StaticLookup lookup(const std::string& url_path, StaticFile& out) const;

  /// The allow-list behind /vendor/.
  static const std::vector<VendorFile>& vendorFiles();
  /// "text/javascript; charset=utf-8" for ".js", ...; empty for extensions that are never served.
  static std::string mimeTypeOf(const std::string& path);

 private:
  StaticLookup resolve(const std::string& relative, StaticFile& out) const;

  std::string root_;
};

}  // namespace dash::http
