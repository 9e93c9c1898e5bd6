#pragma once
// A windowless OpenGL 3.3 core context for rendering to images (no X server, no display).
//
// Tried in order until one gives OpenGL ≥ 3.3 core:
//   1. EGL on Mesa's surfaceless platform (EGL_MESA_platform_surfaceless; llvmpipe on a machine without
//      a GPU), context made current without a surface (EGL_KHR_surfaceless_context);
//   2. EGL's default display with a 16×16 pbuffer;
//   3. OSMesa (libOSMesa.so.8, opened at run time so that its gl* symbols never clash with libGL's).
// The environment variable SPINMOTOR_GL_BACKEND=egl|osmesa forces one. The constructor also fills the
// function table of gl_api.hpp. Rendering then goes to a Framebuffer object (framebuffer.hpp).
#include <memory>
#include <string>

namespace spinmotor::render {

class OffscreenContext {
 public:
  /// Creates and makes current a context. Throws Error listing why each backend failed.
  OffscreenContext();
  ~OffscreenContext();
  OffscreenContext(const OffscreenContext&) = delete;
  OffscreenContext& operator=(const OffscreenContext&) = delete;

  /// "egl-surfaceless", "egl-pbuffer" or "osmesa", plus the GL renderer string.
  const std::string& description() const { return description_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::string description_;
};

}  // namespace spinmotor::render
