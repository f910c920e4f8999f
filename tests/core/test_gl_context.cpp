// The GL contexts: OpenGL 4.5 core, and KHR_debug reporting every error (the mechanism that makes
// a GL error fail a test).
#include <gtest/gtest.h>

#include "gl/loader.h"
#include "support/gl_fixture.h"

namespace shadowlab {
namespace {

class GLContextTest : public testing::GLTest {};

TEST_F(GLContextTest, IsOpenGL45Core) {
    GLint major = 0, minor = 0, profile = 0;
    glGetIntegerv(GL_MAJOR_VERSION, &major);
    glGetIntegerv(GL_MINOR_VERSION, &minor);
    glGetIntegerv(GL_CONTEXT_PROFILE_MASK, &profile);
    EXPECT_GE(major * 10 + minor, 45);
    EXPECT_TRUE(profile & GL_CONTEXT_CORE_PROFILE_BIT);
    EXPECT_FALSE(context()->renderer().empty());
}

TEST_F(GLContextTest, DebugOutputCountsErrors) {
    int before = glDebugState().errors;
    glEnable(GLenum(0x7FFF));  // not a capability: GL_INVALID_ENUM
    EXPECT_EQ(glDebugState().errors, before + 1);
    EXPECT_FALSE(glDebugState().lastError.empty());
    glDebugState().errors = before;  // the error was the point of this test
}

}  // namespace
}  // namespace shadowlab
