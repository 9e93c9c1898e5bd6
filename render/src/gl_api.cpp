#include "spinmotor/render/gl_api.hpp"

#include <string>

#include "spinmotor/core/error.hpp"

namespace spinmotor::render {

GlApi gl;

void load_gl(GetProcAddress get) {
  GlApi api;
#define SPINMOTOR_GL_LOAD(type, name)                 \
  api.name = reinterpret_cast<type>(get("gl" #name)); \
  if (!api.name) throw Error("OpenGL: the context does not provide gl" #name " (OpenGL 3.3 core needed)");
  SPINMOTOR_GL_FUNCTIONS(SPINMOTOR_GL_LOAD)
#undef SPINMOTOR_GL_LOAD
  GLint major = 0, minor = 0;
  api.GetIntegerv(GL_MAJOR_VERSION, &major);
  api.GetIntegerv(GL_MINOR_VERSION, &minor);
  if (major * 10 + minor < 33) {
    const char* v = reinterpret_cast<const char*>(api.GetString(GL_VERSION));
    throw Error("OpenGL: version " + std::string(v ? v : "?") +
                " is older than the 3.3 core the renderer needs");
  }
  gl = api;
}

}  // namespace spinmotor::render
