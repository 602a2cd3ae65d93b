#include "viewer/texture_quad.h"

#include <algorithm>
#include <initializer_list>
#include <string>
#include <utility>
#include <vector>

#include "core/util/error.h"

namespace prism::viewer {
namespace {

// One triangle covering the viewport, its corners from gl_VertexID: no vertex buffer at all. The frame's row 0
// is the top, GL's texture row 0 the bottom, hence the flipped v.
const char* vertex_source = R"(#version 330 core
out vec2 uv;
void main() {
    vec2 corner = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));
    uv = vec2(corner.x, 1.0 - corner.y);
    gl_Position = vec4(corner * 2.0 - 1.0, 0.0, 1.0);
}
)";

const char* fragment_source = R"(#version 330 core
in vec2 uv;
uniform sampler2D frame;
out vec4 color;
void main() { color = vec4(texture(frame, uv).rgb, 1.0); }
)";

// The same pixels read straight from the shared buffer (a buffer texture over it): texel y * width + x.
const char* buffer_fragment_source = R"(#version 330 core
in vec2 uv;
uniform samplerBuffer frame;
uniform ivec2 size;
out vec4 color;
void main() {
    ivec2 p = clamp(ivec2(uv * vec2(size)), ivec2(0), size - 1);
    color = vec4(texelFetch(frame, p.y * size.x + p.x).rgb, 1.0);
}
)";

// The shared buffer written straight into the framebuffer's color texture, where that is a texture of the frame's
// size (the --headless framebuffer): a compute shader, which the GPU runs on all its multiprocessors. On the H100,
// a compute GPU with few graphics-capable units, this takes GL 0.02 ms of GPU time per 1080p frame where the
// full-screen draw takes 0.16 ms. A window's default framebuffer is no texture: it gets the draw.
const char* compute_source = R"(#version 430
layout(local_size_x = 16, local_size_y = 16) in;
layout(std430, binding = 0) readonly buffer Frame { uint pixels[]; };
layout(rgba8, binding = 0) writeonly uniform image2D target;
uniform ivec2 size;
void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (p.x >= size.x || p.y >= size.y) return;
    vec4 c = unpackUnorm4x8(pixels[p.y * size.x + p.x]);
    imageStore(target, ivec2(p.x, size.y - 1 - p.y), vec4(c.rgb, 1.0));
}
)";

GLuint compile(GLenum type, const char* source) {
    GLuint shader = glCreateShader(type);
    glShaderSource(shader, 1, &source, nullptr);
    glCompileShader(shader);
    GLint ok = GL_FALSE;
    glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        char log[1024] = {};
        glGetShaderInfoLog(shader, sizeof log, nullptr, log);
        glDeleteShader(shader);
        std::string line = log;
        line.erase(std::remove(line.begin(), line.end(), '\n'), line.end());
        throw Error("view: display shader failed to compile: " + line);
    }
    return shader;
}

// One program from its shaders' (type, source) pairs; the shaders are not kept.
GLuint link(std::initializer_list<std::pair<GLenum, const char*>> stages) {
    std::vector<GLuint> shaders;
    try {
        for (auto [type, source] : stages) shaders.push_back(compile(type, source));
    } catch (...) {
        for (GLuint shader : shaders) glDeleteShader(shader);
        throw;
    }
    GLuint program = glCreateProgram();
    for (GLuint shader : shaders) glAttachShader(program, shader);
    glLinkProgram(program);
    for (GLuint shader : shaders) glDeleteShader(shader);
    GLint ok = GL_FALSE;
    glGetProgramiv(program, GL_LINK_STATUS, &ok);
    if (!ok) {
        glDeleteProgram(program);
        throw Error("view: display shader failed to link");
    }
    return program;
}

}  // namespace

TextureQuad::TextureQuad() {
    GLint major = 0, minor = 0;
    glGetIntegerv(GL_MAJOR_VERSION, &major);
    glGetIntegerv(GL_MINOR_VERSION, &minor);
    try {
        program_ = link({{GL_VERTEX_SHADER, vertex_source}, {GL_FRAGMENT_SHADER, fragment_source}});
        buffer_program_ = link({{GL_VERTEX_SHADER, vertex_source}, {GL_FRAGMENT_SHADER, buffer_fragment_source}});
        if (major > 4 || (major == 4 && minor >= 3)) {  // compute shaders: GL 4.3 (a 3.3 context draws instead)
            compute_program_ = link({{GL_COMPUTE_SHADER, compute_source}});
            compute_size_location_ = glGetUniformLocation(compute_program_, "size");
        }
    } catch (...) {
        for (GLuint program : {program_, buffer_program_})
            if (program) glDeleteProgram(program);
        throw;
    }
    glGenVertexArrays(1, &vertex_array_);  // core profile: drawing needs a bound VAO, even an empty one
    glGenTextures(1, &texture_);
    glBindTexture(GL_TEXTURE_2D, texture_);
    // Nearest: the frame is shown 1:1, and a screenshot must return the frame's own pixels.
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
}

TextureQuad::~TextureQuad() {
    if (buffer_texture_) glDeleteTextures(1, &buffer_texture_);
    if (compute_program_) glDeleteProgram(compute_program_);
    glDeleteProgram(buffer_program_);
    glDeleteTextures(1, &texture_);
    glDeleteVertexArrays(1, &vertex_array_);
    glDeleteProgram(program_);
}

void TextureQuad::resize(uint32_t width, uint32_t height) {
    glBindTexture(GL_TEXTURE_2D, texture_);
    if (width == width_ && height == height_) return;
    width_ = width;
    height_ = height;
    glBindBuffer(GL_PIXEL_UNPACK_BUFFER, 0);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, GLsizei(width_), GLsizei(height_), 0, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
}

void TextureQuad::upload_from_host(uint32_t width, uint32_t height, const void* pixels) {
    resize(width, height);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    // Packed words with r in the low byte are R,G,B,A bytes in memory on the little-endian hosts we run on.
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, GLsizei(width_), GLsizei(height_), GL_RGBA, GL_UNSIGNED_BYTE, pixels);
}

void TextureQuad::show_buffer(uint32_t width, uint32_t height, GLuint buffer) {
    buffer_ = buffer;
    compute_target_known_ = false;
    if (!buffer_texture_) glGenTextures(1, &buffer_texture_);
    glBindTexture(GL_TEXTURE_BUFFER, buffer_texture_);
    glTexBuffer(GL_TEXTURE_BUFFER, GL_RGBA8, buffer);
    glBindTexture(GL_TEXTURE_BUFFER, 0);
    width_ = width;
    height_ = height;
    from_buffer_ = true;
}

// The color texture of the bound draw framebuffer, when it has one (0 for a window's default framebuffer or a
// renderbuffer).
GLuint TextureQuad::framebuffer_texture() const {
    GLint framebuffer = 0, type = GL_NONE, name = 0;
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &framebuffer);
    if (framebuffer == 0) return 0;
    glGetFramebufferAttachmentParameteriv(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT0,
                                          GL_FRAMEBUFFER_ATTACHMENT_OBJECT_TYPE, &type);
    if (type != GL_TEXTURE) return 0;
    glGetFramebufferAttachmentParameteriv(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT0,
                                          GL_FRAMEBUFFER_ATTACHMENT_OBJECT_NAME, &name);
    return GLuint(name);
}

void TextureQuad::write_with_compute(GLuint target) {
    glUseProgram(compute_program_);
    glUniform2i(compute_size_location_, GLint(width_), GLint(height_));
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, buffer_);
    glBindImageTexture(0, target, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA8);
    glDispatchCompute((width_ + 15) / 16, (height_ + 15) / 16, 1);
    // Whatever reads the framebuffer next (a draw, glReadPixels for a screenshot) sees the stores.
    glMemoryBarrier(GL_FRAMEBUFFER_BARRIER_BIT | GL_PIXEL_BUFFER_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT);
}

void TextureQuad::draw(int viewport_width, int viewport_height) {
    glViewport(0, 0, viewport_width, viewport_height);
    glDisable(GL_FRAMEBUFFER_SRGB);  // the frame is already sRGB-encoded: pass the bytes through
    if (width_ == 0) {
        glClearColor(0.0f, 0.0f, 0.0f, 1.0f);
        glClear(GL_COLOR_BUFFER_BIT);  // nothing to show yet (the triangle covers everything otherwise)
        return;
    }
    if (compute_program_ && from_buffer_ && viewport_width == int(width_) && viewport_height == int(height_)) {
        // Asked once: a glGet may wait for the driver's own thread, and the window's framebuffer does not change.
        if (!compute_target_known_) {
            compute_target_ = framebuffer_texture();
            compute_target_known_ = true;
        }
        if (compute_target_ != 0) return write_with_compute(compute_target_);
    }
    GLuint program = from_buffer_ ? buffer_program_ : program_;
    glUseProgram(program);
    glActiveTexture(GL_TEXTURE0);
    if (from_buffer_) {
        glBindTexture(GL_TEXTURE_BUFFER, buffer_texture_);
        glUniform2i(glGetUniformLocation(program, "size"), GLint(width_), GLint(height_));
    } else {
        glBindTexture(GL_TEXTURE_2D, texture_);
    }
    glUniform1i(glGetUniformLocation(program, "frame"), 0);
    glBindVertexArray(vertex_array_);
    glDrawArrays(GL_TRIANGLES, 0, 3);
}

}  // namespace prism::viewer
