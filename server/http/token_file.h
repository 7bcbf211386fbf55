#pragma once
// The server's token: every request that changes something (launch, cancel, resume, tags and notes,
// dispatch) must carry it as `Authorization: Bearer TOKEN`. It lives in a file readable by its owner
// only (mode 0600), made at the first start.
#include <string>

namespace dash::http {

struct TokenFile {
  std::string token;
  bool created = false;         ///< this call made the file (print the token once)
  bool too_permissive = false;  ///< an existing file others may read (mode wider than 0600)
};

/// Reads the token (the file's first line, surrounding spaces removed) from `path`, or creates the
/// file (and its folder) with a new random token when it does not exist. Throws InputError when the
/// file cannot be read or written, or holds no token.
TokenFile loadOrCreateToken(const std::string& path);

/// 32 bytes from the kernel's random source as 64 hexadecimal digits.
std::string newRandomToken();

}  // namespace dash::http
