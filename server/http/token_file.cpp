#include "server/http/token_file.h"

#include <fcntl.h>
#include <sys/random.h>
#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "engine/core/check.h"

namespace dash::http {

namespace {

constexpr std::size_t kTokenBytes = 32;

std::string trimmed(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r\n");
  if (b == std::string::npos) return "";
  const auto e = s.find_last_not_of(" \t\r\n");
  return s.substr(b, e - b + 1);
}

}  // namespace

std::string newRandomToken() {
  std::array<unsigned char, kTokenBytes> bytes{};
  std::size_t got = 0;
  while (got < bytes.size()) {
    const ssize_t n = getrandom(bytes.data() + got, bytes.size() - got, 0);
    if (n < 0 && errno == EINTR) continue;
    DASH_DEMAND_MSG(n > 0, "getrandom failed");
    got += static_cast<std::size_t>(n);
  }
  static constexpr char kHex[] = "0123456789abcdef";
  std::string out;
  for (unsigned char b : bytes) {
    out += kHex[b >> 4];
    out += kHex[b & 15];
  }
  return out;
}

TokenFile loadOrCreateToken(const std::string& path) {
  DASH_THROW_UNLESS(!path.empty(), "--token-file: empty path");
  TokenFile out;
  struct stat st {};
  if (stat(path.c_str(), &st) == 0) {
    std::ifstream in(path);
    DASH_THROW_UNLESS(in.good(), "token file " + path + ": cannot read it");
    std::string line;
    std::getline(in, line);
    out.token = trimmed(line);
    DASH_THROW_UNLESS(!out.token.empty(), "token file " + path + " holds no token (delete it to make a new one)");
    out.too_permissive = (st.st_mode & 077) != 0;
    return out;
  }
  const std::filesystem::path parent = std::filesystem::path(path).parent_path();
  if (!parent.empty()) {
    std::error_code ec;
    std::filesystem::create_directories(parent, ec);
    DASH_THROW_UNLESS(!ec, "token file " + path + ": cannot create its folder: " + ec.message());
  }
  out.token = newRandomToken();
  // O_EXCL: two servers starting at once never overwrite each other's token.
  const int fd = open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0600);
  if (fd < 0 && errno == EEXIST) return loadOrCreateToken(path);
  DASH_THROW_UNLESS(fd >= 0, "token file " + path + ": cannot create it: " + std::strerror(errno));
  const std::string text = out.token + "\n";
  const bool ok = write(fd, text.data(), text.size()) == static_cast<ssize_t>(text.size());
  fchmod(fd, 0600);  // whatever the umask
  close(fd);
  DASH_THROW_UNLESS(ok, "token file " + path + ": cannot write it");
  out.created = true;
  return out;
}

}  // namespace dash::http
