/// The OSMesa headless context (gl_context.hpp). The only file that includes <GL/osmesa.h>.
#include "granular/render/gl_context.hpp"

#include <GL/osmesa.h>

#include <array>
#include <utility>

namespace granular::render {

namespace {

// The internal buffer only has to exist for OSMesaMakeCurrent; renderers draw into their own
// framebuffer objects.
constexpr int kBufferSize = 16;  // [px]

/// glGetString fetched through OSMesaGetProcAddress: osmesa.h declares the compatibility
/// prototypes too, but calling through the loader keeps every GL call on one path
/// (docs/architecture.md §2).
std::string glString(GLenum name) {
  using GetString = const GLubyte* (*)(GLenum);
  auto getString = reinterpret_cast<GetString>(OSMesaGetProcAddress("glGetString"));
  if (!getString) return {};
  const GLubyte* s = getString(name);
  return s ? reinterpret_cast<const char*>(s) : std::string{};
}

}  // namespace

struct GlContext::Impl {
  OSMesaContext context = nullptr;
  std::array<unsigned char, kBufferSize * kBufferSize * 4> buffer{};

  ~Impl() {
    if (!context) return;
    if (OSMesaGetCurrentContext() == context) OSMesaMakeCurrent(nullptr, nullptr, 0, 0, 0);
    OSMesaDestroyContext(context);
  }
};

GlContext::GlContext() : impl_(std::make_unique<Impl>()) {
  // Depth 24 for the default framebuffer (unused, but some drivers insist); the version is a
  // minimum: Mesa 22.3's llvmpipe returns 4.5 core.
  const int attributes[] = {OSMESA_FORMAT,
                            OSMESA_RGBA,
                            OSMESA_DEPTH_BITS,
                            24,
                            OSMESA_STENCIL_BITS,
                            0,
                            OSMESA_ACCUM_BITS,
                            0,
                            OSMESA_PROFILE,
                            OSMESA_CORE_PROFILE,
                            OSMESA_CONTEXT_MAJOR_VERSION,
                            3,
                            OSMESA_CONTEXT_MINOR_VERSION,
                            3,
                            0};
  impl_->context = OSMesaCreateContextAttribs(attributes, nullptr);
  if (!impl_->context) {
    throw RenderError(
        "OSMesaCreateContextAttribs failed: no OpenGL 3.3 core profile from OSMesa (needs Mesa's "
        "OSMesa with the llvmpipe driver, libosmesa6 >= 20)");
  }
  makeCurrent();
}

GlContext::~GlContext() = default;
GlContext::GlContext(GlContext&&) noexcept = default;
GlContext& GlContext::operator=(GlContext&&) noexcept = default;

void GlContext::makeCurrent() {
  if (!impl_ || !impl_->context) throw RenderError("GlContext: no context (moved from)");
  if (!OSMesaMakeCurrent(impl_->context, impl_->buffer.data(), GL_UNSIGNED_BYTE, kBufferSize,
                         kBufferSize)) {
    throw RenderError("OSMesaMakeCurrent failed");
  }
  // OSMesa is bottom-up by default; say so explicitly, although nothing reads this buffer.
  OSMesaPixelStore(OSMESA_Y_UP, 1);
}

GlProcLoader GlContext::procLoader() {
  return &OSMesaGetProcAddress;
}

std::string GlContext::renderer() const {
  return glString(GL_RENDERER);
}

std::string GlContext::version() const {
  return glString(GL_VERSION);
}

}  // namespace granular::render
