// A headless EGL context for tests that render in-process. Every GL error reported through
// KHR_debug during a test fails it (TearDown checks the count).
#pragma once
#include <gtest/gtest.h>

#include <memory>

#include "gl_context.h"

namespace shadowlab::testing {

class GLTest : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        if (!context()) context() = createHeadlessContext(GLBackend::Egl);
    }
    void SetUp() override { errorsBefore_ = glDebugState().errors; }
    void TearDown() override {
        EXPECT_EQ(glDebugState().errors, errorsBefore_) << "GL error during the test: " << glDebugState().lastError;
    }
    static std::unique_ptr<GLContext>& context() {
        static std::unique_ptr<GLContext> ctx;
        return ctx;
    }

private:
    int errorsBefore_ = 0;
};

}  // namespace shadowlab::testing
