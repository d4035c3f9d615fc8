#include "cli/progress_bar.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace firelook::cli {
namespace {

std::string formatSeconds(double seconds) {
    if (!std::isfinite(seconds) || seconds < 0) return "--:--";
    const long s = std::lround(seconds);
    char text[32];
    if (s >= 3600)
        std::snprintf(text, sizeof text, "%ld:%02ld:%02ld", s / 3600, (s / 60) % 60, s % 60);
    else
        std::snprintf(text, sizeof text, "%02ld:%02ld", s / 60, s % 60);
    return text;
}

}  // namespace

ProgressBar::ProgressBar(std::string label)
    : label_(std::move(label)),
      start_(std::chrono::steady_clock::now()),
      last_draw_(start_ - std::chrono::seconds(1)),
      interactive_(isatty(STDERR_FILENO) != 0) {}

ProgressBar::~ProgressBar() {
    // An unfinished bar (exception, Ctrl-C) still ends its line.
    if (!finished_ && interactive_) std::fputc('\n', stderr);
}

void ProgressBar::update(double fraction, const std::string& detail) {
    const auto now = std::chrono::steady_clock::now();
    if (now - last_draw_ < std::chrono::milliseconds(100)) return;
    last_draw_ = now;
    draw(fraction, detail, false);
}

void ProgressBar::finish(const std::string& detail) {
    draw(1.0, detail, true);
    finished_ = true;
}

void ProgressBar::draw(double fraction, const std::string& detail, bool final_line) {
    fraction = std::clamp(std::isfinite(fraction) ? fraction : 0.0, 0.0, 1.0);
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    const double eta = fraction > 1e-6 ? elapsed * (1.0 - fraction) / fraction : -1.0;
    const int percent = static_cast<int>(fraction * 100.0);
    if (!interactive_) {
        // Logs (CI, pipes): one line per 10% so the log stays short.
        if (final_line || percent / 10 > last_percent_logged_ / 10 || last_percent_logged_ < 0) {
            std::fprintf(stderr, "%s: %3d%%  elapsed %s  eta %s  %s\n", label_.c_str(), percent,
                         formatSeconds(elapsed).c_str(), formatSeconds(final_line ? 0 : eta).c_str(),
                         detail.c_str());
            last_percent_logged_ = percent;
        }
        return;
    }
    constexpr int kWidth = 30;
    const int filled = static_cast<int>(fraction * kWidth);
    std::string bar(filled, '#');
    bar.resize(kWidth, '.');
    std::fprintf(stderr, "\r%s [%s] %3d%%  %s  eta %s  %s\033[K", label_.c_str(), bar.c_str(), percent,
                 formatSeconds(elapsed).c_str(), formatSeconds(final_line ? 0 : eta).c_str(), detail.c_str());
    if (final_line) std::fputc('\n', stderr);
    std::fflush(stderr);
}

}  // namespace firelook::cli
