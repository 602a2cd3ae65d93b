#include "viewer/frame_display.h"

#include <algorithm>
#include <cctype>

#include "core/error.h"
#include "viewer/gl.h"

namespace prism::viewer {
namespace {

bool contains(std::string text, std::string part) {
    auto lower = [](std::string& s) {
        for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    };
    lower(text);
    lower(part);
    return text.find(part) != std::string::npos;
}

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

// The host-copy path: the frame's RGBA8 bytes go into a texture with glTexSubImage2D every frame.
class HostCopyDisplay final : public FrameDisplay {
public:
    explicit HostCopyDisplay(DisplayPath path) : path_(std::move(path)) {
        GLuint vertex = compile(GL_VERTEX_SHADER, vertex_source);
        GLuint fragment = compile(GL_FRAGMENT_SHADER, fragment_source);
        program_ = glCreateProgram();
        glAttachShader(program_, vertex);
        glAttachShader(program_, fragment);
        glLinkProgram(program_);
        glDeleteShader(vertex);
        glDeleteShader(fragment);
        GLint ok = GL_FALSE;
        glGetProgramiv(program_, GL_LINK_STATUS, &ok);
        if (!ok) throw Error("view: display shader failed to link");
        glGenVertexArrays(1, &vertex_array_);   // core profile: drawing needs a bound VAO, even an empty one
        glGenTextures(1, &texture_);
        glBindTexture(GL_TEXTURE_2D, texture_);
        // Nearest: the frame is shown 1:1, and a screenshot must return the frame's own pixels.
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    }
    ~HostCopyDisplay() override {
        glDeleteTextures(1, &texture_);
        glDeleteVertexArrays(1, &vertex_array_);
        glDeleteProgram(program_);
    }

    const DisplayPath& path() const override { return path_; }

    void update(const FrameResult& frame) override {
        if (frame.image.size() != size_t(frame.width) * frame.height)
            throw Error("view: frame has " + std::to_string(frame.image.size()) + " pixels, expected " +
                        std::to_string(size_t(frame.width) * frame.height));
        glBindTexture(GL_TEXTURE_2D, texture_);
        glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
        if (frame.width != width_ || frame.height != height_) {
            width_ = frame.width;
            height_ = frame.height;
            glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, GLsizei(width_), GLsizei(height_), 0, GL_RGBA,
                         GL_UNSIGNED_BYTE, nullptr);
        }
        // Packed words with r in the low byte are R,G,B,A bytes in memory on the little-endian hosts we run on.
        glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, GLsizei(width_), GLsizei(height_), GL_RGBA, GL_UNSIGNED_BYTE,
                        frame.image.data());
    }

    void draw(int viewport_width, int viewport_height) override {
        glViewport(0, 0, viewport_width, viewport_height);
        glDisable(GL_FRAMEBUFFER_SRGB);
        glClearColor(0.0f, 0.0f, 0.0f, 1.0f);
        glClear(GL_COLOR_BUFFER_BIT);
        if (width_ == 0) return;
        glUseProgram(program_);
        glActiveTexture(GL_TEXTURE0);
        glBindTexture(GL_TEXTURE_2D, texture_);
        glUniform1i(glGetUniformLocation(program_, "frame"), 0);
        glBindVertexArray(vertex_array_);
        glDrawArrays(GL_TRIANGLES, 0, 3);
    }

private:
    DisplayPath path_;
    GLuint program_ = 0, vertex_array_ = 0, texture_ = 0;
    uint32_t width_ = 0, height_ = 0;
};

}  // namespace

DisplayPath choose_display_path(const BackendInfo& backend) {
    const std::string& api = backend.name;
    const std::string& device = backend.device;
    if (api == "cpu" || api == "cpu-ref") return {"host copy", "the frame is already in host memory"};
    if (api == "opencl" && (contains(device, "pthread") || contains(device, "portable computing")))
        return {"host copy", "PoCL has no GL sharing"};
    if (api == "vulkan" && (contains(device, "llvmpipe") || contains(device, "lavapipe")))
        return {"host copy", "lavapipe has no GL sharing"};
    if (api == "cuda") return {"host copy", "CUDA-GL interop not implemented yet"};
    if (api == "opencl") return {"host copy", "cl_khr_gl_sharing not implemented yet"};
    if (api == "vulkan") return {"host copy", "Vulkan external memory not implemented yet"};
    return {"host copy", "no interop for backend " + api};
}

std::unique_ptr<FrameDisplay> create_frame_display(const BackendInfo& backend) {
    return std::make_unique<HostCopyDisplay>(choose_display_path(backend));
}

}  // namespace prism::viewer
