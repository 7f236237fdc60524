// GL errors: every failing GL call is reported with the call's text, file and line.
#pragma once

#include <stdexcept>
#include <string>

namespace bt::gl {

// Thrown for anything the GL renderer cannot do: no context, a shader that does not compile
// at run time, a GL call that set an error, a scene too large for the context's limits.
class GlError : public std::runtime_error {
public:
  using std::runtime_error::runtime_error;
};

// Reads glGetError() after `call` and throws GlError naming it, when set. Checking after every
// call costs a driver round trip, which matters in the viewer's per-frame loop only; uploads and
// dispatches are few.
void checkGlError(const char* call, const char* file, int line);

const char* glErrorName(unsigned error);

} // namespace bt::gl

// Runs a GL call and reports any error it set, with the call's source text.
#define BT_GL(call)                                                                                                                        \
  do {                                                                                                                                     \
    call;                                                                                                                                  \
    ::bt::gl::checkGlError(#call, __FILE__, __LINE__);                                                                                     \
  } while (0)
