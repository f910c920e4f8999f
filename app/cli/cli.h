// The command line (DESIGN.md section 6). Each command returns the process exit code:
// 0 ok, 2 bad input (InputError), 1 internal failure.
#pragma once
#include <string>
#include <vector>

namespace shadowlab {

int runCommandLine(const std::vector<std::string>& args);
// The window (app/window/window.cpp): the rendered image, technique and scene switched with keys.
int runWindow(const std::vector<std::string>& args);
// `shadowlab` with no arguments: the window, or with no display a headless render of the default
// scene into a folder, printed (never exit code 1 for a missing display).
int runDefault();
// `bench` (app/bench/cmd_bench.cpp) and `figure` (app/bench/cmd_figure.cpp).
int commandBench(const std::vector<std::string>& args);
// `bench --calibrate` (app/bench/calibrate.cpp): the table `auto` predicts from.
int commandCalibrate(const std::vector<std::string>& args);
int commandFigure(const std::vector<std::string>& args);

// Option parsing shared by the commands: "--flag value" pairs and bare flags, checked against the
// command's known options, so a typo is an error that names it.
class Options {
public:
    Options(const std::string& command, const std::vector<std::string>& args, size_t first,
            const std::vector<std::string>& valued, const std::vector<std::string>& bare);
    bool has(const std::string& flag) const;
    std::string get(const std::string& flag, const std::string& fallback = "") const;
    std::vector<std::string> all(const std::string& flag) const;  // repeated flags (--set)
    const std::vector<std::string>& positional() const { return positional_; }
    int getInt(const std::string& flag, int fallback, int lo, int hi) const;
    float getFloat(const std::string& flag, float fallback, float lo, float hi) const;

private:
    std::string command_;
    std::vector<std::pair<std::string, std::string>> values_;
    std::vector<std::string> positional_;
};

// "WxH" with each side in 1..8192.
void parseSize(const std::string& text, int& width, int& height);

}  // namespace shadowlab
