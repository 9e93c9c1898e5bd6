#include "spinmotor/render/framebuffer.hpp"

#include <algorithm>
#include <string>

#include "spinmotor/core/error.hpp"
#include "spinmotor/render/gl_api.hpp"

namespace spinmotor::render {

Framebuffer::Framebuffer(int width, int height, int samples) : width_(width), height_(height) {
  if (width < 1 || height < 1 || width > 16384 || height > 16384)
    throw Error("image size " + std::to_string(width) + "x" + std::to_string(height) + " outside [1, 16384]");
  GLint max_samples = 0;
  gl.GetIntegerv(GL_MAX_SAMPLES, &max_samples);
  samples_ = std::clamp(samples, 0, int(max_samples));
  gl.GenRenderbuffers(3, rb_);
  gl.GenFramebuffers(1, &fbo_ms_);
  gl.GenFramebuffers(1, &fbo_resolve_);
  gl.BindFramebuffer(GL_FRAMEBUFFER, fbo_ms_);
  gl.BindRenderbuffer(GL_RENDERBUFFER, rb_[0]);
  gl.RenderbufferStorageMultisample(GL_RENDERBUFFER, samples_, GL_RGBA8, width, height);
  gl.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, rb_[0]);
  gl.BindRenderbuffer(GL_RENDERBUFFER, rb_[1]);
  gl.RenderbufferStorageMultisample(GL_RENDERBUFFER, samples_, GL_DEPTH_COMPONENT24, width, height);
  gl.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, rb_[1]);
  if (gl.CheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
    throw Error("OpenGL: incomplete multisampled framebuffer of " + std::to_string(width) + "x" +
                std::to_string(height));
  gl.BindFramebuffer(GL_FRAMEBUFFER, fbo_resolve_);
  gl.BindRenderbuffer(GL_RENDERBUFFER, rb_[2]);
  gl.RenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, width, height);
  gl.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, rb_[2]);
  if (gl.CheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
    throw Error("OpenGL: incomplete framebuffer of " + std::to_string(width) + "x" + std::to_string(height));
  gl.BindFramebuffer(GL_FRAMEBUFFER, 0);
}

Framebuffer::~Framebuffer() {
  gl.DeleteFramebuffers(1, &fbo_ms_);
  gl.DeleteFramebuffers(1, &fbo_resolve_);
  gl.DeleteRenderbuffers(3, rb_);
}

void Framebuffer::bind() { gl.BindFramebuffer(GL_FRAMEBUFFER, fbo_ms_); }

Image Framebuffer::read() {
  gl.BindFramebuffer(GL_READ_FRAMEBUFFER, fbo_ms_);
  gl.BindFramebuffer(GL_DRAW_FRAMEBUFFER, fbo_resolve_);
  gl.BlitFramebuffer(0, 0, width_, height_, 0, 0, width_, height_, GL_COLOR_BUFFER_BIT, GL_NEAREST);
  gl.BindFramebuffer(GL_READ_FRAMEBUFFER, fbo_resolve_);
  gl.PixelStorei(GL_PACK_ALIGNMENT, 1);
  Image im;
  im.width = width_, im.height = height_;
  std::vector<std::uint8_t> bottom_up(std::size_t(width_) * height_ * 4);
  gl.ReadPixels(0, 0, width_, height_, GL_RGBA, GL_UNSIGNED_BYTE, bottom_up.data());
  gl.BindFramebuffer(GL_FRAMEBUFFER, 0);
  if (const GLenum e = gl.GetError(); e != GL_NO_ERROR)
    throw Error("OpenGL error " + std::to_string(e) + " while rendering");
  im.rgba.resize(bottom_up.size());
  const std::size_t row = std::size_t(width_) * 4;
  for (int y = 0; y < height_; ++y) std::copy_n(&bottom_up[(height_ - 1 - y) * row], row, &im.rgba[y * row]);
  return im;
}

}  // namespace spinmotor::render
