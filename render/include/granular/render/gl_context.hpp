#pragma once
/// A headless OpenGL 3.3 core context (OSMesa, Mesa's software rasterizer llvmpipe), and the two
/// things every GL drawing class needs from whatever context it runs in: an error type and a
/// function that looks up GL entry points.
///
/// The drawing code (ParticleRenderer) never sees OSMesa: it takes a GlProcLoader, so a window
/// front end can hand it glfwGetProcAddress instead of GlContext::procLoader(). This header does
/// not include <GL/osmesa.h> (which drags in the compatibility <GL/gl.h>) for the same reason.
#include <memory>
#include <stdexcept>
#include <string>

namespace granular::render {

/// A renderer or context failure: OSMesa or the core profile unavailable, a shader that does not
/// compile, an incomplete framebuffer, a size beyond the GL limits.
class RenderError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A GL entry point as returned by a get-proc-address function (cast to its real type before use).
using GlProc = void (*)();
/// Looks up a GL entry point by name ("glDrawArraysInstanced"); returns nullptr if unknown.
/// OSMesaGetProcAddress and glfwGetProcAddress both have this type.
using GlProcLoader = GlProc (*)(const char* name);

/// An OSMesa OpenGL ≥ 3.3 core-profile context with a 24-bit depth buffer, current on the
/// constructing thread on construction.
///
/// It draws into a tiny internal RGBA buffer that nothing reads: renderers draw into their own
/// framebuffer objects, at whatever size they need. OSMesa contexts are current per thread;
/// GL objects created in this context (renderers) must be destroyed before it, on a thread
/// where it is current.
class GlContext {
 public:
  /// Creates the context and makes it current. Throws RenderError if OSMesa cannot create a
  /// 3.3 core profile (e.g. an OSMesa built without llvmpipe, or one too old).
  GlContext();
  ~GlContext();
  GlContext(const GlContext&) = delete;
  GlContext& operator=(const GlContext&) = delete;
  GlContext(GlContext&&) noexcept;
  GlContext& operator=(GlContext&&) noexcept;

  /// Makes this context current on the calling thread (throws RenderError on failure).
  void makeCurrent();

  /// OSMesaGetProcAddress, for ParticleRenderer and other GL code.
  static GlProcLoader procLoader();

  /// GL_RENDERER of the current context (this one unless another was made current since),
  /// e.g. "llvmpipe (LLVM 15.0.6, 256 bits)".
  std::string renderer() const;
  /// GL_VERSION of the current context, e.g. "4.5 (Core Profile) Mesa 22.3.6".
  std::string version() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace granular::render
