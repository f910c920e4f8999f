// The draw both penumbra volume techniques share: the volume quads' triangles, three vec4 per
// vertex in pvm/volume.vert's layout (the position, then two attributes each fragment shader reads
// its own way), uploaded to a buffer that grows as needed and rasterized from the light into the
// framebuffer bound by the caller. pvm fills the attributes with the edge's end points, its index
// and the side (volume.frag); pvmf with the edge distance d_e (pvmf/mask.frag).
#pragma once
#include <algorithm>
#include <glm/glm.hpp>
#include <string>
#include <vector>

#include "gl/buffer.h"
#include "gl/program.h"
#include "graph/frame.h"

namespace shadowlab {

class VolumeDraw {
public:
    // Cleared by begin(): append three vec4 per vertex, then draw().
    std::vector<glm::vec4>& begin(size_t vertices) {
        vertices_.clear();
        vertices_.reserve(vertices * 3);
        return vertices_;
    }
    void draw(PassContext& ctx, const std::string& fragment) {
        if (vertices_.empty()) {
            return;
        }
        const size_t bytes = vertices_.size() * sizeof(glm::vec4);
        if (buffer_.bytes() < bytes) {
            buffer_ = Buffer(bytes * 2);
            vao_.bindVertexBuffer(0, buffer_, 0, 3 * sizeof(glm::vec4));
            for (GLuint a = 0; a < 3; ++a) vao_.attribute(a, 0, 4, GL_FLOAT, a * GLuint(sizeof(glm::vec4)));
        }
        buffer_.upload(vertices_.data(), bytes);
        const ShaderProgram& program = ctx.programs().get("pvm/volume.vert", fragment);
        program.use();
        program.set("lightViewFromWorld", ctx.lightView().viewFromWorld);
        program.set("lightClipFromView", ctx.lightView().clipFromView);
        vao_.bind();
        glDrawArrays(GL_TRIANGLES, 0, GLsizei(vertices_.size() / 3));
        glBindVertexArray(0);
    }

private:
    std::vector<glm::vec4> vertices_;
    Buffer buffer_;
    VertexArray vao_;
};

}  // namespace shadowlab
