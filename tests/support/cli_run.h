// Running the shadowlab binary from a test: its exit code and what it printed.
#pragma once
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <string>

namespace shadowlab::test {

struct Result {
    int code = -1;
    std::string output;  // stdout and stderr
};

// Runs `shadowlab <arguments>` through the shell, stderr merged into stdout.
inline Result run(const std::string& arguments) {
    std::string command = std::string(SHADOWLAB_BINARY) + " " + arguments + " 2>&1";
    Result r;
    FILE* pipe = popen(command.c_str(), "r");
    if (!pipe) return r;
    char buffer[4096];
    size_t n;
    while ((n = fread(buffer, 1, sizeof buffer, pipe)) > 0) r.output.append(buffer, n);
    int status = pclose(pipe);
    r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return r;
}

// A path in the current test's own folder under SHADOWLAB_TEST_TMP/<group>/<Suite>.<Test>/:
// ctest runs tests in parallel, and bad-input checks look for stray temporaries in the folder.
inline std::string testPath(const std::string& group, const std::string& name) {
    const ::testing::TestInfo* test = ::testing::UnitTest::GetInstance()->current_test_info();
    const std::filesystem::path dir = std::filesystem::path(SHADOWLAB_TEST_TMP) / group /
                                      (std::string(test->test_suite_name()) + "." + test->name());
    std::filesystem::create_directories(dir);
    return (dir / name).string();
}

}  // namespace shadowlab::test
