// A terminal progress bar with an ETA for long work (bake, reference).
// Writes to stderr so stdout stays clean for --json output; redraws at most
// ten times a second and only when stderr is a terminal (plain lines otherwise).
#pragma once

#include <chrono>
#include <string>

namespace firelook::cli {

class ProgressBar {
public:
    explicit ProgressBar(std::string label);
    ~ProgressBar();
    // fraction in [0, 1]; detail is a short suffix such as "frame 3/12".
    void update(double fraction, const std::string& detail = {});
    void finish(const std::string& detail = {});

private:
    void draw(double fraction, const std::string& detail, bool final_line);

    std::string label_;
    std::chrono::steady_clock::time_point start_;
    std::chrono::steady_clock::time_point last_draw_;
    bool interactive_;
    bool finished_ = false;
    int last_percent_logged_ = -1;
};

}  // namespace firelook::cli
