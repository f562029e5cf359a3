#pragma once
/// The OpenGL 3.3 core entry points the renderer uses, fetched through a GlProcLoader.
///
/// Why a loader of our own: libOSMesa exports the gl* symbols itself, and linking libGL as well
/// binds them to libglvnd, where every call silently does nothing (docs/architecture.md §2).
/// Fetching each entry point through the context's get-proc-address function (OSMesaGetProcAddress
/// here, glfwGetProcAddress in a window) works in both and links nothing. <GL/glcorearb.h> gives
/// the function-pointer types without prototypes (GL_GLEXT_PROTOTYPES stays undefined).
///
/// Do not include this next to <GL/gl.h> or <GL/osmesa.h>: the two headers clash.
#include <GL/glcorearb.h>

#include "granular/render/gl_context.hpp"

namespace granular::render {

// X(name without the gl prefix, the same in capitals as in PFNGL<NAME>PROC)
#define GRANULAR_GL_FUNCTIONS(X)                      \
  X(ActiveTexture, ACTIVETEXTURE)                     \
  X(AttachShader, ATTACHSHADER)                       \
  X(BindBuffer, BINDBUFFER)                           \
  X(BindFramebuffer, BINDFRAMEBUFFER)                 \
  X(BindRenderbuffer, BINDRENDERBUFFER)               \
  X(BindTexture, BINDTEXTURE)                         \
  X(BindVertexArray, BINDVERTEXARRAY)                 \
  X(BlendFuncSeparate, BLENDFUNCSEPARATE)             \
  X(BufferData, BUFFERDATA)                           \
  X(CheckFramebufferStatus, CHECKFRAMEBUFFERSTATUS)   \
  X(Clear, CLEAR)                                     \
  X(ClearColor, CLEARCOLOR)                           \
  X(ClearDepth, CLEARDEPTH)                           \
  X(ColorMask, COLORMASK)                             \
  X(CompileShader, COMPILESHADER)                     \
  X(CreateProgram, CREATEPROGRAM)                     \
  X(CreateShader, CREATESHADER)                       \
  X(DeleteBuffers, DELETEBUFFERS)                     \
  X(DeleteFramebuffers, DELETEFRAMEBUFFERS)           \
  X(DeleteProgram, DELETEPROGRAM)                     \
  X(DeleteRenderbuffers, DELETERENDERBUFFERS)         \
  X(DeleteShader, DELETESHADER)                       \
  X(DeleteTextures, DELETETEXTURES)                   \
  X(DeleteVertexArrays, DELETEVERTEXARRAYS)           \
  X(DepthFunc, DEPTHFUNC)                             \
  X(DepthMask, DEPTHMASK)                             \
  X(DetachShader, DETACHSHADER)                       \
  X(Disable, DISABLE)                                 \
  X(DrawArrays, DRAWARRAYS)                           \
  X(DrawArraysInstanced, DRAWARRAYSINSTANCED)         \
  X(Enable, ENABLE)                                   \
  X(EnableVertexAttribArray, ENABLEVERTEXATTRIBARRAY) \
  X(Finish, FINISH)                                   \
  X(FramebufferRenderbuffer, FRAMEBUFFERRENDERBUFFER) \
  X(FramebufferTexture2D, FRAMEBUFFERTEXTURE2D)       \
  X(GenBuffers, GENBUFFERS)                           \
  X(GenFramebuffers, GENFRAMEBUFFERS)                 \
  X(GenRenderbuffers, GENRENDERBUFFERS)               \
  X(GenTextures, GENTEXTURES)                         \
  X(GenVertexArrays, GENVERTEXARRAYS)                 \
  X(GetError, GETERROR)                               \
  X(GetIntegerv, GETINTEGERV)                         \
  X(GetProgramInfoLog, GETPROGRAMINFOLOG)             \
  X(GetProgramiv, GETPROGRAMIV)                       \
  X(GetShaderInfoLog, GETSHADERINFOLOG)               \
  X(GetShaderiv, GETSHADERIV)                         \
  X(GetString, GETSTRING)                             \
  X(GetUniformLocation, GETUNIFORMLOCATION)           \
  X(IsEnabled, ISENABLED)                             \
  X(LinkProgram, LINKPROGRAM)                         \
  X(PixelStorei, PIXELSTOREI)                         \
  X(ReadBuffer, READBUFFER)                           \
  X(ReadPixels, READPIXELS)                           \
  X(RenderbufferStorage, RENDERBUFFERSTORAGE)         \
  X(ShaderSource, SHADERSOURCE)                       \
  X(TexImage2D, TEXIMAGE2D)                           \
  X(TexParameteri, TEXPARAMETERI)                     \
  X(Uniform1f, UNIFORM1F)                             \
  X(Uniform1i, UNIFORM1I)                             \
  X(Uniform2f, UNIFORM2F)                             \
  X(Uniform3f, UNIFORM3F)                             \
  X(Uniform4f, UNIFORM4F)                             \
  X(UniformMatrix4fv, UNIFORMMATRIX4FV)               \
  X(UseProgram, USEPROGRAM)                           \
  X(VertexAttribDivisor, VERTEXATTRIBDIVISOR)         \
  X(VertexAttribPointer, VERTEXATTRIBPOINTER)         \
  X(Viewport, VIEWPORT)

/// One table of GL entry points, filled from a loader. Call as `gl.DrawArrays(...)`. Entry
/// points may differ between contexts on some platforms (WGL), so each renderer owns its table.
struct GlFunctions {
#define GRANULAR_GL_DECLARE(name, NAME) PFNGL##NAME##PROC name = nullptr;
  GRANULAR_GL_FUNCTIONS(GRANULAR_GL_DECLARE)
#undef GRANULAR_GL_DECLARE

  /// Looks every entry point up; throws RenderError naming the ones the loader does not know,
  /// or if the current context is older than OpenGL 3.3.
  explicit GlFunctions(GlProcLoader loader);
};

}  // namespace granular::render
