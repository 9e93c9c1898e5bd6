#pragma once
// The OpenGL 3.3 core functions the renderer uses, loaded through the current platform's
// get-proc-address (EGL, OSMesa or GLFW) into one table. Calling through pointers (instead of linking
// libGL's symbols) lets one binary use an EGL context, an OSMesa context (whose library exports its own
// gl* symbols) or a GLFW window without symbol clashes.
#include <GL/glcorearb.h>

namespace spinmotor::render {

#define SPINMOTOR_GL_FUNCTIONS(X)                                            \
  X(PFNGLGETERRORPROC, GetError)                                             \
  X(PFNGLGETSTRINGPROC, GetString)                                           \
  X(PFNGLGETINTEGERVPROC, GetIntegerv)                                       \
  X(PFNGLVIEWPORTPROC, Viewport)                                             \
  X(PFNGLCLEARCOLORPROC, ClearColor)                                         \
  X(PFNGLCLEARPROC, Clear)                                                   \
  X(PFNGLENABLEPROC, Enable)                                                 \
  X(PFNGLDISABLEPROC, Disable)                                               \
  X(PFNGLDEPTHFUNCPROC, DepthFunc)                                           \
  X(PFNGLBLENDFUNCPROC, BlendFunc)                                           \
  X(PFNGLPIXELSTOREIPROC, PixelStorei)                                       \
  X(PFNGLREADPIXELSPROC, ReadPixels)                                         \
  X(PFNGLFINISHPROC, Finish)                                                 \
  X(PFNGLDRAWELEMENTSPROC, DrawElements)                                     \
  X(PFNGLDRAWARRAYSPROC, DrawArrays)                                         \
  X(PFNGLGENVERTEXARRAYSPROC, GenVertexArrays)                               \
  X(PFNGLBINDVERTEXARRAYPROC, BindVertexArray)                               \
  X(PFNGLDELETEVERTEXARRAYSPROC, DeleteVertexArrays)                         \
  X(PFNGLGENBUFFERSPROC, GenBuffers)                                         \
  X(PFNGLBINDBUFFERPROC, BindBuffer)                                         \
  X(PFNGLBUFFERDATAPROC, BufferData)                                         \
  X(PFNGLBUFFERSUBDATAPROC, BufferSubData)                                   \
  X(PFNGLDELETEBUFFERSPROC, DeleteBuffers)                                   \
  X(PFNGLVERTEXATTRIBPOINTERPROC, VertexAttribPointer)                       \
  X(PFNGLENABLEVERTEXATTRIBARRAYPROC, EnableVertexAttribArray)               \
  X(PFNGLCREATESHADERPROC, CreateShader)                                     \
  X(PFNGLSHADERSOURCEPROC, ShaderSource)                                     \
  X(PFNGLCOMPILESHADERPROC, CompileShader)                                   \
  X(PFNGLGETSHADERIVPROC, GetShaderiv)                                       \
  X(PFNGLGETSHADERINFOLOGPROC, GetShaderInfoLog)                             \
  X(PFNGLDELETESHADERPROC, DeleteShader)                                     \
  X(PFNGLCREATEPROGRAMPROC, CreateProgram)                                   \
  X(PFNGLATTACHSHADERPROC, AttachShader)                                     \
  X(PFNGLBINDATTRIBLOCATIONPROC, BindAttribLocation)                         \
  X(PFNGLLINKPROGRAMPROC, LinkProgram)                                       \
  X(PFNGLGETPROGRAMIVPROC, GetProgramiv)                                     \
  X(PFNGLGETPROGRAMINFOLOGPROC, GetProgramInfoLog)                           \
  X(PFNGLUSEPROGRAMPROC, UseProgram)                                         \
  X(PFNGLDELETEPROGRAMPROC, DeleteProgram)                                   \
  X(PFNGLGETUNIFORMLOCATIONPROC, GetUniformLocation)                         \
  X(PFNGLUNIFORM1IPROC, Uniform1i)                                           \
  X(PFNGLUNIFORM1FPROC, Uniform1f)                                           \
  X(PFNGLUNIFORM2FPROC, Uniform2f)                                           \
  X(PFNGLUNIFORM3FPROC, Uniform3f)                                           \
  X(PFNGLUNIFORMMATRIX4FVPROC, UniformMatrix4fv)                             \
  X(PFNGLGENTEXTURESPROC, GenTextures)                                       \
  X(PFNGLBINDTEXTUREPROC, BindTexture)                                       \
  X(PFNGLACTIVETEXTUREPROC, ActiveTexture)                                   \
  X(PFNGLTEXIMAGE2DPROC, TexImage2D)                                         \
  X(PFNGLTEXPARAMETERIPROC, TexParameteri)                                   \
  X(PFNGLTEXBUFFERPROC, TexBuffer)                                           \
  X(PFNGLDELETETEXTURESPROC, DeleteTextures)                                 \
  X(PFNGLGENFRAMEBUFFERSPROC, GenFramebuffers)                               \
  X(PFNGLBINDFRAMEBUFFERPROC, BindFramebuffer)                               \
  X(PFNGLFRAMEBUFFERRENDERBUFFERPROC, FramebufferRenderbuffer)               \
  X(PFNGLCHECKFRAMEBUFFERSTATUSPROC, CheckFramebufferStatus)                 \
  X(PFNGLDELETEFRAMEBUFFERSPROC, DeleteFramebuffers)                         \
  X(PFNGLGENRENDERBUFFERSPROC, GenRenderbuffers)                             \
  X(PFNGLBINDRENDERBUFFERPROC, BindRenderbuffer)                             \
  X(PFNGLRENDERBUFFERSTORAGEPROC, RenderbufferStorage)                       \
  X(PFNGLRENDERBUFFERSTORAGEMULTISAMPLEPROC, RenderbufferStorageMultisample) \
  X(PFNGLDELETERENDERBUFFERSPROC, DeleteRenderbuffers)                       \
  X(PFNGLBLITFRAMEBUFFERPROC, BlitFramebuffer)

struct GlApi {
#define SPINMOTOR_GL_MEMBER(type, name) type name = nullptr;
  SPINMOTOR_GL_FUNCTIONS(SPINMOTOR_GL_MEMBER)
#undef SPINMOTOR_GL_MEMBER
};

/// The process-wide table (filled by load_gl).
extern GlApi gl;

using GetProcAddress = void* (*)(const char* name);

/// Loads every function of the table through `get` (with the "gl" prefix added). Needs a current
/// OpenGL ≥ 3.3 context. Throws Error naming the first missing function, or the version if < 3.3.
void load_gl(GetProcAddress get);

}  // namespace spinmotor::render
