/// The GL entry-point table (gl_functions.hpp).
#include "gl_functions.hpp"

#include <string>

namespace granular::render {

GlFunctions::GlFunctions(GlProcLoader loader) {
  if (!loader) throw RenderError("GL loader: no get-proc-address function given");
  std::string missing;
#define GRANULAR_GL_LOAD(name, NAME)                              \
  name = reinterpret_cast<PFNGL##NAME##PROC>(loader("gl" #name)); \
  if (!name) missing += (missing.empty() ? "gl" : ", gl") + std::string(#name);
  GRANULAR_GL_FUNCTIONS(GRANULAR_GL_LOAD)
#undef GRANULAR_GL_LOAD
  if (!missing.empty()) throw RenderError("GL loader: entry points not found: " + missing);

  // A loader answers for names whatever context is current (or none), so check that a 3.3
  // context really is current before anything draws: without one every call is a silent no-op.
  GLint major = 0, minor = 0;
  GetIntegerv(GL_MAJOR_VERSION, &major);
  GetIntegerv(GL_MINOR_VERSION, &minor);
  if (major * 10 + minor < 33) {
    throw RenderError("GL loader: need a current OpenGL 3.3 context, found version " +
                      std::to_string(major) + "." + std::to_string(minor) +
                      (major == 0 ? " (is a context current on this thread?)" : ""));
  }
}

}  // namespace granular::render
