// Progress of a long run on stderr, once it has taken more than two seconds, every 10%:
// "reference: 512/1024 light samples (50%, 4.1 s)".
#pragma once
#include <chrono>
#include <cstdio>
#include <string>

namespace shadowlab {

class ProgressReporter {
public:
    ProgressReporter(std::string what, std::string unit) : what_(std::move(what)), unit_(std::move(unit)) {}
    void update(size_t done, size_t total) {
        double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
        int percent = total ? int(done * 100 / total) : 100;
        if (seconds > 2.0 && percent >= reported_ + 10) {
            reported_ = percent - percent % 10;
            std::fprintf(stderr, "%s: %zu/%zu %s (%d%%, %.1f s)\n", what_.c_str(), done, total, unit_.c_str(), percent,
                         seconds);
        }
    }

private:
    std::string what_, unit_;
    std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
    int reported_ = 0;
};

}  // namespace shadowlab
