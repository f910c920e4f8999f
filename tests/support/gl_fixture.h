// A headless EGL context for tests that render in-process. Every GL error reported through
// KHR_debug during a test fails it (TearDown checks the count), and so does setting a uniform that
// no stage of the program declares (the uniform name check is on for every GL test).
#pragma once
#include <gtest/gtest.h>

#include <memory>

#include "gl/context.h"
#include "gl/program.h"

namespace shadowlab::testing {

class GLTest : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        if (!context()) context() = createHeadlessContext(GLBackend::Egl);
        setUniformNameCheck(true);
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
