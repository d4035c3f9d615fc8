// Per-stage timings of the last frames, for the on-screen panel and --timings.
// Stages (milliseconds, wall clock; the GL stages end with glFinish so they include the GPU's
// work, which on llvmpipe runs on the CPU cores):
//   update  fl_world_update + reading state and coefficients (+ the CPU image and flare when used)
//   upload  textures: U and optical depths on a frame change (including the library's decoding
//           of the frame), z every frame (GPU path); the CPU image and flare (CPU path)
//   draw    the reconstruction pass (GPU path) and the display pass
//   frame   the whole loop iteration (in the window: also the UI and the buffer swap)
#pragma once

#include <algorithm>
#include <deque>
#include <vector>

namespace firelook::viewer {

struct StageTimes {
    double update_ms = 0.0, upload_ms = 0.0, draw_ms = 0.0, frame_ms = 0.0;
};

class FrameTimings {
  public:
    explicit FrameTimings(size_t capacity = 240) : capacity_(capacity) {}
    void push(const StageTimes& t) {
        history_.push_back(t);
        if (history_.size() > capacity_) history_.pop_front();
    }
    void clear() { history_.clear(); }
    size_t size() const { return history_.size(); }
    StageTimes last() const { return history_.empty() ? StageTimes{} : history_.back(); }
    StageTimes median() const {
        return {medianOf(&StageTimes::update_ms), medianOf(&StageTimes::upload_ms), medianOf(&StageTimes::draw_ms),
                medianOf(&StageTimes::frame_ms)};
    }
    // A larger window for --timings (every frame of the run).
    void setCapacity(size_t capacity) { capacity_ = capacity; }

  private:
    double medianOf(double StageTimes::*field) const {
        if (history_.empty()) return 0.0;
        std::vector<double> v;
        v.reserve(history_.size());
        for (const StageTimes& t : history_) v.push_back(t.*field);
        std::nth_element(v.begin(), v.begin() + static_cast<long>(v.size() / 2), v.end());
        return v[v.size() / 2];
    }

    size_t capacity_;
    std::deque<StageTimes> history_;
};

}  // namespace firelook::viewer
