#pragma once
// An off-screen render target: multisampled colour + depth renderbuffers, resolved into a single-sample
// RGBA8 buffer that read() returns as an Image (top row first). Needs a current context (gl_api.hpp).
#include "spinmotor/render/image.hpp"

namespace spinmotor::render {

class Framebuffer {
 public:
  /// width×height pixels (each in [1, 16384]) and up to `samples` MSAA samples (clamped to the
  /// implementation's maximum). Throws Error on a bad size or an incomplete framebuffer.
  Framebuffer(int width, int height, int samples = 4);
  ~Framebuffer();
  Framebuffer(const Framebuffer&) = delete;
  Framebuffer& operator=(const Framebuffer&) = delete;

  void bind();   ///< draw into the multisampled buffer
  Image read();  ///< resolves and reads the pixels (waits for the GPU)
  int width() const { return width_; }
  int height() const { return height_; }

 private:
  int width_, height_, samples_ = 0;
  unsigned fbo_ms_ = 0, fbo_resolve_ = 0, rb_[3] = {0, 0, 0};
};

}  // namespace spinmotor::render
