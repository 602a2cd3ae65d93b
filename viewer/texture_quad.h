// The frame on screen, drawn 1:1 as a full-viewport triangle: from an RGBA8 texture filled from host memory (the
// host-copy path), or read in the fragment shader straight from the GL buffer the device copied it into (the
// interop paths: a buffer texture over it, so GL makes no copy of its own). With an interop buffer and a
// framebuffer whose color buffer is a texture of the frame's size (--headless), a compute shader writes the buffer
// into that texture instead of drawing (GL 4.3+; much cheaper on a GPU with few graphics units). Needs a current GL
// 3.3+ core context.
#pragma once

#include <cstdint>

#include "core/util/non_copyable.h"
#include "viewer/gl.h"

namespace prism::viewer {

class TextureQuad : private NonCopyable {
public:
    TextureQuad();  // throws prism::Error when the shaders do not build
    ~TextureQuad();

    // RGBA8 pixels, row 0 at the top, packed words with r in the low byte.
    void upload_from_host(uint32_t width, uint32_t height, const void* pixels);
    // From now on, draw reads the frame from offset 0 of the GL buffer `buffer` itself (same layout), whatever it
    // holds at draw time.
    void show_buffer(uint32_t width, uint32_t height, GLuint buffer);
    // Draws the frame over the viewport (clears it before the first upload), or writes it there (see above).
    void draw(int viewport_width, int viewport_height);

private:
    void resize(uint32_t width, uint32_t height);
    GLuint framebuffer_texture() const;
    void write_with_compute(GLuint target);

    GLuint program_ = 0, vertex_array_ = 0, texture_ = 0;
    GLuint buffer_program_ = 0, buffer_texture_ = 0;
    GLuint compute_program_ = 0, buffer_ = 0;  // the compute path (GL 4.3+) and the shared buffer it reads
    GLint compute_size_location_ = -1;
    GLuint compute_target_ = 0;  // the framebuffer's color texture, 0: none (draw instead)
    bool compute_target_known_ = false;
    bool from_buffer_ = false;
    uint32_t width_ = 0, height_ = 0;
};

}  // namespace prism::viewer
