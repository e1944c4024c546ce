#pragma once
// OpenGL 3.3 core entry points. They are linked directly from the GL dispatch library
// (libOpenGL, GLVND), which forwards each call to the current context, window (GLX) or
// offscreen (EGL) alike: no loader is needed.
#ifndef GL_GLEXT_PROTOTYPES
#define GL_GLEXT_PROTOTYPES 1
#endif
#include <GL/glcorearb.h>
