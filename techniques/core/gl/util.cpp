#include "gl/util.h"

namespace shadowlab {

void drawFullscreenTriangle() {
    static GLuint vao = 0;
    if (!vao) glCreateVertexArrays(1, &vao);
    glBindVertexArray(vao);
    glDrawArrays(GL_TRIANGLES, 0, 3);
}

}  // namespace shadowlab
