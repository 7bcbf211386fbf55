#pragma once
// Two kinds of failure, as in Drake: a broken invariant is a bug and aborts (DASH_DEMAND);
// bad caller input throws a typed error that the CLI prints and the server turns into a 4xx.
#include <stdexcept>
#include <string>

namespace dash {

/// Bad input from a user or a file: the message names the offending field.
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

[[noreturn]] void abortWithMessage(const char* condition, const char* file, int line,
                                   const std::string& message);

}  // namespace dash

#define DASH_DEMAND(cond)                                                   \
  do {                                                                      \
    if (!(cond)) ::dash::abortWithMessage(#cond, __FILE__, __LINE__, "");   \
  } while (false)

#define DASH_DEMAND_MSG(cond, msg)                                          \
  do {                                                                      \
    if (!(cond)) ::dash::abortWithMessage(#cond, __FILE__, __LINE__, msg);  \
  } while (false)

#define DASH_THROW_UNLESS(cond, msg)                     \
  do {                                                   \
    if (!(cond)) throw ::dash::InputError(msg);          \
  } while (false)
