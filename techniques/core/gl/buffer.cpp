#include "gl/buffer.h"

#include "error.h"

namespace shadowlab {

Buffer::Buffer(size_t bytes, const void* data) : bytes_(bytes) {
    if (bytes == 0) throw InternalError("Buffer: a buffer needs at least one byte");
    glCreateBuffers(1, &id_);
    glNamedBufferStorage(id_, GLsizeiptr(bytes), data, GL_DYNAMIC_STORAGE_BIT | GL_MAP_READ_BIT);
    detail::countBuffer(1, int64_t(bytes_));
}
Buffer::~Buffer() {
    if (id_) {
        glDeleteBuffers(1, &id_);
        detail::countBuffer(-1, -int64_t(bytes_));
    }
}
Buffer::Buffer(Buffer&& o) noexcept : id_(o.id_), bytes_(o.bytes_) {
    o.id_ = 0;
    o.bytes_ = 0;
}
Buffer& Buffer::operator=(Buffer&& o) noexcept {
    if (this != &o) {
        if (id_) {
            glDeleteBuffers(1, &id_);
            detail::countBuffer(-1, -int64_t(bytes_));
        }
        id_ = o.id_;
        bytes_ = o.bytes_;
        o.id_ = 0;
        o.bytes_ = 0;
    }
    return *this;
}

void Buffer::upload(const void* data, size_t bytes, size_t offset) const {
    if (offset + bytes > bytes_)
        throw InternalError("Buffer::upload: " + std::to_string(bytes) + " bytes at offset " + std::to_string(offset) +
                            " do not fit in " + std::to_string(bytes_));
    glNamedBufferSubData(id_, GLintptr(offset), GLsizeiptr(bytes), data);
}
void Buffer::clear() const { glClearNamedBufferData(id_, GL_R8UI, GL_RED_INTEGER, GL_UNSIGNED_BYTE, nullptr); }
void Buffer::readBytes(void* out, size_t bytes, size_t offset) const {
    if (offset + bytes > bytes_)
        throw InternalError("Buffer::read: " + std::to_string(bytes) + " bytes at offset " + std::to_string(offset) +
                            " do not fit in " + std::to_string(bytes_));
    if (bytes) glGetNamedBufferSubData(id_, GLintptr(offset), GLsizeiptr(bytes), out);
}
void Buffer::bindBase(GLenum target, GLuint index) const { glBindBufferBase(target, index, id_); }

VertexArray::VertexArray() { glCreateVertexArrays(1, &id_); }
VertexArray::~VertexArray() {
    if (id_) glDeleteVertexArrays(1, &id_);
}
VertexArray::VertexArray(VertexArray&& o) noexcept : id_(o.id_) { o.id_ = 0; }
VertexArray& VertexArray::operator=(VertexArray&& o) noexcept {
    if (this != &o) {
        if (id_) glDeleteVertexArrays(1, &id_);
        id_ = o.id_;
        o.id_ = 0;
    }
    return *this;
}
void VertexArray::bindVertexBuffer(GLuint binding, const Buffer& buffer, GLintptr offset, GLsizei stride) const {
    glVertexArrayVertexBuffer(id_, binding, buffer.id(), offset, stride);
}
void VertexArray::attribute(GLuint index, GLuint binding, GLint components, GLenum type, GLuint relativeOffset,
                            bool normalized) const {
    glEnableVertexArrayAttrib(id_, index);
    glVertexArrayAttribFormat(id_, index, components, type, normalized ? GL_TRUE : GL_FALSE, relativeOffset);
    glVertexArrayAttribBinding(id_, index, binding);
}
void VertexArray::attributeInteger(GLuint index, GLuint binding, GLint components, GLenum type,
                                   GLuint relativeOffset) const {
    glEnableVertexArrayAttrib(id_, index);
    glVertexArrayAttribIFormat(id_, index, components, type, relativeOffset);
    glVertexArrayAttribBinding(id_, index, binding);
}
void VertexArray::setElementBuffer(const Buffer& buffer) const { glVertexArrayElementBuffer(id_, buffer.id()); }

}  // namespace shadowlab
