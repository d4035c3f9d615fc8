// Which keyframes a keyed value blends at a frame, and with what weight: the one bracketing rule
// of the runtime's keyframes (look_track.h), the viewer's keyed reference look and `firelook
// animate`. Header-only and dependency-free, so the viewer and the CLI use it without linking the
// runtime.
#pragma once

#include <algorithm>
#include <cstddef>
#include <iterator>

namespace firelook::world {

// The value at a frame is (1 - t) keys[lo] + t keys[hi].
struct KeyframeBracket {
    size_t lo = 0;
    size_t hi = 0;   // == lo where one key holds alone
    double t = 0.0;  // in [0, 1]; 0 where one key holds
};

// `keys`: non-empty, sorted by a numeric member `frame` (the runtime's resolved keys, the viewer's
// edited keys and animate's whole-frame keys alike). Before the first key the first holds, from
// the last key on the last, exactly on a key that key; in between, t = (frame - f_lo) / (f_hi -
// f_lo). Of several keys at one frame the last holds from that frame on, so the value jumps there.
// A NaN frame holds the first key. Allocation-free; a linear scan, as keys are few.
template <class Keys>
KeyframeBracket bracketKeyframes(const Keys& keys, double frame) {
    const size_t n = std::size(keys);
    size_t hi = 0;
    while (hi < n && keys[hi].frame <= frame) ++hi;  // the first key after `frame`
    if (hi == 0) return {0, 0, 0.0};
    const size_t lo = hi - 1;
    const double f_lo = static_cast<double>(keys[lo].frame);
    if (hi == n || f_lo == frame) return {lo, lo, 0.0};
    const double f_hi = static_cast<double>(keys[hi].frame);
    if (!(f_hi > f_lo)) return {lo, lo, 0.0};  // a NaN key frame, which no sort orders
    return {lo, hi, std::clamp((frame - f_lo) / (f_hi - f_lo), 0.0, 1.0)};
}

}  // namespace firelook::world
