// The project's one check for programmer errors (broken preconditions,
// invalid options handed to a constructor): on failure it prints the file,
// line, condition and a message to stderr and aborts, in every build type.
// Expected runtime failures (no tag in view, a bad file) are reported by
// return values, never by RIPPLE_CHECK.
//
//   RIPPLE_CHECK(options.IsValid(&error), "invalid options: " + error);
//
// The message (anything a std::string can be built from) is evaluated only
// when the check fails.
#ifndef RIPPLE_GEOMETRY_CHECK_H_
#define RIPPLE_GEOMETRY_CHECK_H_

#include <cstdio>
#include <cstdlib>
#include <string>

namespace ripple::geometry::internal {

[[noreturn]] inline void CheckFailed(const char* file, int line,
                                     const char* condition,
                                     const std::string& message) {
  std::fprintf(stderr, "%s:%d: check failed: %s: %s\n", file, line, condition,
               message.c_str());
  std::fflush(stderr);
  std::abort();
}

}  // namespace ripple::geometry::internal

#define RIPPLE_CHECK(condition, message)                                \
  do {                                                                  \
    if (!(condition)) {                                                 \
      ::ripple::geometry::internal::CheckFailed(__FILE__, __LINE__,     \
                                                #condition, (message)); \
    }                                                                   \
  } while (false)

#endif  // RIPPLE_GEOMETRY_CHECK_H_
