#include "viewer/offscreen.hpp"

#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <cstdio>
#include <stdexcept>
#include <string>

#include "viewer/renderer.hpp"

namespace tactus::viewer {
namespace {

std::string egl_error(const char* what) {
  return std::string("offscreen rendering: ") + what + " (EGL error 0x" + [] {
    char hex[16];
    std::snprintf(hex, sizeof hex, "%04x", static_cast<unsigned>(eglGetError()));
    return std::string(hex);
  }() + "); it needs Mesa's EGL (Debian: libegl1, libegl-mesa0, libgl1-mesa-dri)";
}

}  // namespace

OffscreenContext::OffscreenContext() {
  const auto get_display =
      reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
  EGLDisplay display = EGL_NO_DISPLAY;
  // Surfaceless needs neither a window system nor a GPU; the default display is the fallback.
  if (get_display) display = get_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
  if (display == EGL_NO_DISPLAY) display = eglGetDisplay(EGL_DEFAULT_DISPLAY);
  if (display == EGL_NO_DISPLAY) throw std::runtime_error(egl_error("no EGL display"));
  EGLint major = 0, minor = 0;
  if (!eglInitialize(display, &major, &minor)) throw std::runtime_error(egl_error("EGL does not initialize"));
  if (!eglBindAPI(EGL_OPENGL_API)) {
    eglTerminate(display);
    throw std::runtime_error(egl_error("EGL offers no desktop OpenGL"));
  }
  const EGLint config_attributes[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
  EGLConfig config = nullptr;
  EGLint configs = 0;
  eglChooseConfig(display, config_attributes, &config, 1, &configs);
  const EGLint context_attributes[] = {EGL_CONTEXT_MAJOR_VERSION, 3, EGL_CONTEXT_MINOR_VERSION, 3,
                                       EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                       EGL_NONE};
  // Surfaceless displays often list no config: a context without one is then allowed.
  EGLContext context = eglCreateContext(display, configs > 0 ? config : EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT,
                                        context_attributes);
  if (context == EGL_NO_CONTEXT) {
    const std::string message = egl_error("no OpenGL 3.3 core context");
    eglTerminate(display);
    throw std::runtime_error(message);
  }
  if (!eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context)) {
    const std::string message = egl_error("the context cannot be made current without a surface");
    eglDestroyContext(display, context);
    eglTerminate(display);
    throw std::runtime_error(message);
  }
  display_ = display;
  context_ = context;
}

OffscreenContext::~OffscreenContext() {
  eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  eglDestroyContext(display_, context_);
  eglTerminate(display_);
}

OffscreenTarget::OffscreenTarget(int width, int height) : width_(width), height_(height) {
  GLint max_size = 0;
  glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &max_size);
  if (width < 1 || height < 1 || width > max_size || height > max_size)
    throw std::runtime_error("offscreen rendering: a " + std::to_string(width) + "x" + std::to_string(height) +
                             " image is outside what the driver renders (1 to " + std::to_string(max_size) + " per side)");
  glGenRenderbuffers(1, &colour_ms_);
  glBindRenderbuffer(GL_RENDERBUFFER, colour_ms_);
  glRenderbufferStorageMultisample(GL_RENDERBUFFER, 4, GL_RGBA8, width, height);
  glGenRenderbuffers(1, &depth_ms_);
  glBindRenderbuffer(GL_RENDERBUFFER, depth_ms_);
  glRenderbufferStorageMultisample(GL_RENDERBUFFER, 4, GL_DEPTH_COMPONENT24, width, height);
  glGenFramebuffers(1, &multisampled_);
  glBindFramebuffer(GL_FRAMEBUFFER, multisampled_);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, colour_ms_);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth_ms_);
  const GLenum ms_status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
  glGenRenderbuffers(1, &colour_);
  glBindRenderbuffer(GL_RENDERBUFFER, colour_);
  glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, width, height);
  glGenFramebuffers(1, &resolved_);
  glBindFramebuffer(GL_FRAMEBUFFER, resolved_);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, colour_);
  const GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  if (ms_status != GL_FRAMEBUFFER_COMPLETE || status != GL_FRAMEBUFFER_COMPLETE)
    throw std::runtime_error("offscreen rendering: the framebuffer is incomplete");
}

OffscreenTarget::~OffscreenTarget() {
  glDeleteFramebuffers(1, &multisampled_);
  glDeleteFramebuffers(1, &resolved_);
  glDeleteRenderbuffers(1, &colour_ms_);
  glDeleteRenderbuffers(1, &depth_ms_);
  glDeleteRenderbuffers(1, &colour_);
}

void OffscreenTarget::bind() const { glBindFramebuffer(GL_FRAMEBUFFER, multisampled_); }

std::vector<std::uint8_t> OffscreenTarget::read() const {
  glBindFramebuffer(GL_READ_FRAMEBUFFER, multisampled_);
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, resolved_);
  glBlitFramebuffer(0, 0, width_, height_, 0, 0, width_, height_, GL_COLOR_BUFFER_BIT, GL_NEAREST);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, resolved_);
  std::vector<std::uint8_t> rgb = read_rgb(width_, height_);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  return rgb;
}

}  // namespace tactus::viewer
