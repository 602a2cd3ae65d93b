#include "viewer/interop_display.h"

#include <string>

#include "core/util/error.h"
#include "viewer/gl_memory_import.h"
#include "viewer/texture_quad.h"

namespace prism::viewer {
namespace {

class InteropDisplay final : public FrameDisplay {
public:
    InteropDisplay(DisplayPath path, GlInterop& interop, uint32_t width, uint32_t height)
        : path_(std::move(path)), interop_(interop), width_(width), height_(height) {
        const size_t bytes = this->bytes();
        if (interop_.device_owns_memory()) {
            imported_ = std::make_unique<ImportedBuffer>(interop_.export_buffer(bytes), bytes);
            buffer_ = imported_->buffer();
        } else {
            while (glGetError() != GL_NO_ERROR) {
            }
            glGenBuffers(1, &own_buffer_);
            glBindBuffer(GL_TEXTURE_BUFFER, own_buffer_);
            // Written by the device, read by GL's draw through a buffer texture.
            glBufferData(GL_TEXTURE_BUFFER, GLsizeiptr(bytes), nullptr, GL_DYNAMIC_COPY);
            glBindBuffer(GL_TEXTURE_BUFFER, 0);
            if (glGetError() != GL_NO_ERROR) {
                glDeleteBuffers(1, &own_buffer_);
                throw Error("view: cannot create a GL buffer of " + std::to_string(bytes) + " bytes");
            }
            buffer_ = own_buffer_;
            // The device's first access (OpenCL's acquire in particular) must find GL done with the new buffer.
            glFinish();
            try {
                interop_.attach_gl_buffer(buffer_, bytes);
            } catch (...) {
                glDeleteBuffers(1, &own_buffer_);
                throw;
            }
        }
        quad_.show_buffer(width_, height_, buffer_);
        // The frame's copy waits for GL's last draw from the buffer where the API does not (a GL fence).
        interop_.set_gl_idle_wait([this] {
            if (fence_) wait_for_gl();
        });
    }

    ~InteropDisplay() override {
        interop_.set_gl_idle_wait({});
        if (fence_) glDeleteSync(fence_);
        if (own_buffer_) glDeleteBuffers(1, &own_buffer_);
    }

    const DisplayPath& path() const override { return path_; }

    void update(const FrameResult& frame) override {
        if (frame.width != width_ || frame.height != height_)
            throw Error("view: frame is " + std::to_string(frame.width) + "x" + std::to_string(frame.height) +
                        ", the shared buffer " + std::to_string(width_) + "x" + std::to_string(height_));
        // The frame's submission already copied it into the shared buffer (RenderSettings::copy_to_gl).
        if (semaphores()) imported_->wait_ready();
    }

    // GL reads the shared buffer in the draw itself (no upload into a texture first): the device may write it
    // again only after that.
    void draw(int viewport_width, int viewport_height) override {
        quad_.draw(viewport_width, viewport_height);
        if (semaphores()) {
            imported_->signal_released();
        } else if (interop_.needs_gl_idle_before_copy()) {
            fence_ = glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0);
        }
    }

private:
    size_t bytes() const { return size_t(width_) * height_ * 4; }
    bool semaphores() const { return imported_ && imported_->has_semaphores(); }

    void wait_for_gl() {
        // The first wait flushes, so the fence cannot wait on commands still sitting in GL's queue.
        GLenum status = glClientWaitSync(fence_, GL_SYNC_FLUSH_COMMANDS_BIT, 5'000'000'000ull);
        glDeleteSync(fence_);
        fence_ = nullptr;
        if (status == GL_TIMEOUT_EXPIRED || status == GL_WAIT_FAILED)
            throw Error("view: GL did not finish reading the shared buffer within 5 s");
    }

    DisplayPath path_;
    GlInterop& interop_;
    uint32_t width_, height_;
    TextureQuad quad_;
    std::unique_ptr<ImportedBuffer> imported_;  // Vulkan-GL, CUDA-GL through external memory
    GLuint own_buffer_ = 0;                     // OpenCL-GL, CUDA-GL with a registered buffer
    GLuint buffer_ = 0;
    GLsync fence_ = nullptr;
};

}  // namespace

std::unique_ptr<FrameDisplay> create_interop_display(DisplayPath path, GlInterop& interop, uint32_t width,
                                                     uint32_t height) {
    return std::make_unique<InteropDisplay>(std::move(path), interop, width, height);
}

}  // namespace prism::viewer
