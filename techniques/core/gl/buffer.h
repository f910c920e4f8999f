// GPU buffers (storage, atomic counter, uniform, indirect arguments, vertices) and vertex arrays.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "gl/format.h"
#include "gl/loader.h"

namespace shadowlab {

// The argument records of glDispatchComputeIndirect and glDrawArraysIndirect, laid out as GL reads
// them, so a compute shader can write them into a Buffer (as uint[3] / uint[4]).
struct DispatchIndirectCommand {
    uint32_t numGroupsX = 0, numGroupsY = 1, numGroupsZ = 1;
};
static_assert(sizeof(DispatchIndirectCommand) == 12);
struct DrawArraysIndirectCommand {
    uint32_t count = 0, instanceCount = 1, first = 0, baseInstance = 0;
};
static_assert(sizeof(DrawArraysIndirectCommand) == 16);

// Immutable storage (GL_DYNAMIC_STORAGE_BIT | GL_MAP_READ_BIT): the size is fixed, the contents
// change through upload(), clear() and shaders. Counted in gpuMemory().
class Buffer {
public:
    Buffer() = default;
    explicit Buffer(size_t bytes, const void* data = nullptr);  // bytes > 0
    ~Buffer();
    Buffer(Buffer&& other) noexcept;
    Buffer& operator=(Buffer&& other) noexcept;
    Buffer(const Buffer&) = delete;
    Buffer& operator=(const Buffer&) = delete;

    GLuint id() const { return id_; }
    size_t bytes() const { return bytes_; }
    explicit operator bool() const { return id_ != 0; }

    void upload(const void* data, size_t bytes, size_t offset = 0) const;
    void clear() const;  // every byte 0
    // The whole buffer as Ts (bytes() / sizeof(T) of them); waits for the GPU.
    template <class T>
    std::vector<T> read() const {
        std::vector<T> values(bytes_ / sizeof(T));
        readBytes(values.data(), values.size() * sizeof(T), 0);
        return values;
    }
    void readBytes(void* out, size_t bytes, size_t offset) const;
    // target: GL_SHADER_STORAGE_BUFFER, GL_ATOMIC_COUNTER_BUFFER or GL_UNIFORM_BUFFER.
    void bindBase(GLenum target, GLuint index) const;

private:
    GLuint id_ = 0;
    size_t bytes_ = 0;
};

// A vertex array object: where each vertex attribute comes from. It owns no memory of its own
// (bytes() = 0): the Buffers it reads count themselves.
class VertexArray {
public:
    VertexArray();
    ~VertexArray();
    VertexArray(VertexArray&& other) noexcept;
    VertexArray& operator=(VertexArray&& other) noexcept;
    VertexArray(const VertexArray&) = delete;
    VertexArray& operator=(const VertexArray&) = delete;

    GLuint id() const { return id_; }
    size_t bytes() const { return 0; }

    void bindVertexBuffer(GLuint binding, const Buffer& buffer, GLintptr offset, GLsizei stride) const;
    // A float attribute (vecN in the shader); integer `type`s are converted, normalised if asked.
    void attribute(GLuint index, GLuint binding, GLint components, GLenum type, GLuint relativeOffset,
                   bool normalized = false) const;
    // An integer attribute (ivecN / uvecN in the shader), read without conversion.
    void attributeInteger(GLuint index, GLuint binding, GLint components, GLenum type, GLuint relativeOffset) const;
    void setElementBuffer(const Buffer& buffer) const;
    void bind() const { glBindVertexArray(id_); }

private:
    GLuint id_ = 0;
};

}  // namespace shadowlab
