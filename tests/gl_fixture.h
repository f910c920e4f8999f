// A headless EGL context for tests that render in-process. Every GL error reported through
// KHR_debug during a test fails it (TearDown checks the count), and so does setting a uniform that
// no stage of the program declares (the uniform name check is on for every GL test).
#pragma once
#include <gtest/gtest.h>

#include <memory>

#include "gl_context.h"
#include "gl_program.h"

namespace shadowlab::testing {

class GLTest : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        if (!context()) context() = createHeadlessContext(GLBackend::Egl);
        setUniformNameCheck(true);
        // Known offender: GpuScene::draw (renderer.cpp) sets the per-object material uniforms on
        // every program, the shadow-depth program included, which declares none of them. Remove
        // these once the renderer sets them only where they are declared.
        for (const char* uniform : {"albedo", "objectId", "receivesShadows"})
            allowUndeclaredUniform("common/shadow_depth.vert + common/shadow_depth.frag", uniform);
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
