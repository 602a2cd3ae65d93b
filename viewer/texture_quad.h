// The frame on screen: one RGBA8 texture drawn 1:1 as a full-viewport triangle, filled either from host memory
// (the host-copy path) or from a pixel-unpack buffer on the device (the interop paths). Needs a current GL 3.3+
// core context.
#pragma once

#include <cstdint>

#include "viewer/gl.h"

namespace prism::viewer {

class TextureQuad {
public:
    TextureQuad();   // throws prism::Error when the shaders do not build
    ~TextureQuad();
    TextureQuad(const TextureQuad&) = delete;
    TextureQuad& operator=(const TextureQuad&) = delete;

    // RGBA8 pixels, row 0 at the top, packed words with r in the low byte.
    void upload_from_host(uint32_t width, uint32_t height, const void* pixels);
    // The same layout, from offset 0 of a GL buffer (bound as GL_PIXEL_UNPACK_BUFFER for the upload).
    void upload_from_buffer(uint32_t width, uint32_t height, GLuint buffer);
    // Clears the viewport and draws the texture over it (nothing before the first upload).
    void draw(int viewport_width, int viewport_height);

private:
    void resize(uint32_t width, uint32_t height);

    GLuint program_ = 0, vertex_array_ = 0, texture_ = 0;
    uint32_t width_ = 0, height_ = 0;
};

}  // namespace prism::viewer
