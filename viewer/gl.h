// OpenGL without a loader: Mesa's and NVIDIA's libGL export every core entry point, so the prototypes are enough.
#pragma once

#ifndef GL_GLEXT_PROTOTYPES
#define GL_GLEXT_PROTOTYPES
#endif
#include <GL/glcorearb.h>
