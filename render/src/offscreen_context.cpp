#include "spinmotor/render/offscreen_context.hpp"

#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <dlfcn.h>

#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "spinmotor/core/error.hpp"
#include "spinmotor/render/gl_api.hpp"

namespace spinmotor::render {
namespace {

// OSMesa's entry points, declared here instead of including <GL/osmesa.h> (which pulls <GL/gl.h>, whose
// declarations clash with <GL/glcorearb.h> used by gl_api.hpp).
using OSMesaContext = void*;
constexpr int kOsmesaRgba = 0x1908, kOsmesaDepthBits = 0x30, kOsmesaStencilBits = 0x31, kOsmesaProfile = 0x33,
              kOsmesaCoreProfile = 0x34, kOsmesaMajor = 0x36, kOsmesaMinor = 0x37, kOsmesaFormat = 0x22;
constexpr unsigned kGlUnsignedByte = 0x1401;
using OSMesaCreateContextAttribsFn = OSMesaContext (*)(const int* attribs, OSMesaContext share);
using OSMesaMakeCurrentFn = unsigned char (*)(OSMesaContext, void* buffer, unsigned type, int w, int h);
using OSMesaDestroyContextFn = void (*)(OSMesaContext);
using OSMesaGetProcAddressFn = void* (*)(const char*);

OSMesaGetProcAddressFn g_osmesa_get = nullptr;
void* osmesa_get(const char* name) { return g_osmesa_get(name); }
void* egl_get(const char* name) { return reinterpret_cast<void*>(eglGetProcAddress(name)); }

bool has_extension(const char* list, const char* name) {
  if (!list) return false;
  const std::size_t n = std::strlen(name);
  for (const char* p = list; (p = std::strstr(p, name)); p += n)
    if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0')) return true;
  return false;
}

}  // namespace

struct OffscreenContext::Impl {
  EGLDisplay display = EGL_NO_DISPLAY;
  EGLContext context = EGL_NO_CONTEXT;
  EGLSurface surface = EGL_NO_SURFACE;
  void* osmesa_lib = nullptr;
  OSMesaContext osmesa = nullptr;
  std::vector<unsigned char> osmesa_buffer;

  ~Impl() { release(); }

  void release() {
    if (display != EGL_NO_DISPLAY) {
      eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
      if (surface != EGL_NO_SURFACE) eglDestroySurface(display, surface);
      if (context != EGL_NO_CONTEXT) eglDestroyContext(display, context);
      eglTerminate(display);
      display = EGL_NO_DISPLAY;
      surface = EGL_NO_SURFACE;
      context = EGL_NO_CONTEXT;
    }
    if (osmesa) {
      reinterpret_cast<OSMesaDestroyContextFn>(dlsym(osmesa_lib, "OSMesaDestroyContext"))(osmesa);
      osmesa = nullptr;
    }
    if (osmesa_lib) {
      dlclose(osmesa_lib);
      osmesa_lib = nullptr;
    }
  }

  // Returns "" on success, else why it failed.
  std::string try_egl(bool surfaceless) {
    const char* client_ext = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    if (surfaceless) {
      if (!has_extension(client_ext, "EGL_MESA_platform_surfaceless"))
        return "no EGL_MESA_platform_surfaceless";
      auto get_platform_display =
          reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
      if (!get_platform_display) return "no eglGetPlatformDisplayEXT";
      display = get_platform_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    } else {
      display = eglGetDisplay(EGL_DEFAULT_DISPLAY);
    }
    if (display == EGL_NO_DISPLAY) return "no display";
    EGLint major = 0, minor = 0;
    if (!eglInitialize(display, &major, &minor)) {
      display = EGL_NO_DISPLAY;
      return "eglInitialize failed";
    }
    if (!eglBindAPI(EGL_OPENGL_API)) return "eglBindAPI(EGL_OPENGL_API) failed";
    const EGLint config_attribs[] = {EGL_SURFACE_TYPE, surfaceless ? 0 : EGL_PBUFFER_BIT, EGL_RENDERABLE_TYPE,
                                     EGL_OPENGL_BIT, EGL_NONE};
    EGLConfig config;
    EGLint count = 0;
    if (!eglChooseConfig(display, config_attribs, &config, 1, &count) || count < 1) return "no OpenGL config";
    const EGLint ctx_attribs[] = {EGL_CONTEXT_MAJOR_VERSION,
                                  3,
                                  EGL_CONTEXT_MINOR_VERSION,
                                  3,
                                  EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                  EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                  EGL_NONE};
    context = eglCreateContext(display, config, EGL_NO_CONTEXT, ctx_attribs);
    if (context == EGL_NO_CONTEXT) return "no OpenGL 3.3 core context";
    if (!surfaceless) {
      const EGLint pb[] = {EGL_WIDTH, 16, EGL_HEIGHT, 16, EGL_NONE};
      surface = eglCreatePbufferSurface(display, config, pb);
      if (surface == EGL_NO_SURFACE) return "no pbuffer";
    }
    if (!eglMakeCurrent(display, surface, surface, context)) return "eglMakeCurrent failed";
    return "";
  }

  std::string try_osmesa() {
    osmesa_lib = dlopen("libOSMesa.so.8", RTLD_NOW | RTLD_LOCAL);
    if (!osmesa_lib) osmesa_lib = dlopen("libOSMesa.so", RTLD_NOW | RTLD_LOCAL);
    if (!osmesa_lib) return "libOSMesa not found";
    auto create =
        reinterpret_cast<OSMesaCreateContextAttribsFn>(dlsym(osmesa_lib, "OSMesaCreateContextAttribs"));
    auto make_current = reinterpret_cast<OSMesaMakeCurrentFn>(dlsym(osmesa_lib, "OSMesaMakeCurrent"));
    g_osmesa_get = reinterpret_cast<OSMesaGetProcAddressFn>(dlsym(osmesa_lib, "OSMesaGetProcAddress"));
    if (!create || !make_current || !g_osmesa_get) return "libOSMesa lacks OSMesaCreateContextAttribs";
    const int attribs[] = {kOsmesaFormat,
                           kOsmesaRgba,
                           kOsmesaDepthBits,
                           24,
                           kOsmesaStencilBits,
                           0,
                           kOsmesaProfile,
                           kOsmesaCoreProfile,
                           kOsmesaMajor,
                           3,
                           kOsmesaMinor,
                           3,
                           0};
    osmesa = create(attribs, nullptr);
    if (!osmesa) return "no OpenGL 3.3 core context";
    osmesa_buffer.assign(16 * 16 * 4, 0);
    if (!make_current(osmesa, osmesa_buffer.data(), kGlUnsignedByte, 16, 16))
      return "OSMesaMakeCurrent failed";
    return "";
  }
};

OffscreenContext::OffscreenContext() : impl_(std::make_unique<Impl>()) {
  const char* forced = std::getenv("SPINMOTOR_GL_BACKEND");
  const std::string force = forced ? forced : "";
  std::string why;
  auto attempt = [&](const char* name, auto&& fn, GetProcAddress get) {
    if (!force.empty() && std::string(name).rfind(force, 0) != 0) return false;
    std::string err = fn();
    if (err.empty()) {
      try {
        load_gl(get);
        const char* r = reinterpret_cast<const char*>(gl.GetString(GL_RENDERER));
        description_ = std::string(name) + " (" + (r ? r : "?") + ")";
        return true;
      } catch (const Error& e) {
        err = e.what();
      }
    }
    why += std::string(why.empty() ? "" : "; ") + name + ": " + err;
    impl_->release();
    return false;
  };
  if (attempt(
          "egl-surfaceless", [&] { return impl_->try_egl(true); }, egl_get))
    return;
  if (attempt(
          "egl-pbuffer", [&] { return impl_->try_egl(false); }, egl_get))
    return;
  if (attempt(
          "osmesa", [&] { return impl_->try_osmesa(); }, osmesa_get))
    return;
  throw Error("no offscreen OpenGL 3.3 context: " +
              (why.empty() ? "SPINMOTOR_GL_BACKEND=" + force + " unknown" : why));
}

OffscreenContext::~OffscreenContext() = default;

}  // namespace spinmotor::render
