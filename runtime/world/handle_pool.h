// The one handle pool (after sokol_gfx and EnTT), used by the world for its
// instances and by the C plugin for packages, looks, worlds and instances.
//
// An id is 32 bits: kind (3 bits) | generation (11 bits, 1..2047) | index + 1
// (18 bits). 0 is never valid (no kind is 0); an id of another kind, a freed
// slot or an older generation is refused. A slot whose generation is spent
// (2047 uses) is retired, never reused, so a released handle never becomes
// valid again, however often slots are reused (sokol_gfx wraps the generation
// instead). The price: a pool makes at most kCapacity x 2047 = 5.4e8 objects
// over its life (at 1,000 a second, 6 days without a restart), then refuses
// new ones with Error(Limit) saying so; a 64-bit id would lift that, at an ABI
// change of every handle struct. Not synchronised.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "common/error.h"

namespace firelook::world {

class InvalidHandle : public Error {
  public:
    explicit InvalidHandle(const std::string& message) : Error(ErrorCode::InvalidHandle, message) {}
};

enum class HandleKind : uint32_t { Package = 1, Look = 2, World = 3, Instance = 4 };

inline const char* toString(HandleKind kind) {
    switch (kind) {
        case HandleKind::Package: return "package";
        case HandleKind::Look: return "look";
        case HandleKind::World: return "world";
        case HandleKind::Instance: return "instance";
    }
    return "unknown";
}

template <typename T>
class HandlePool {
  public:
    static constexpr uint32_t kIndexBits = 18, kGenerationBits = 11, kKindShift = kIndexBits + kGenerationBits;
    static constexpr uint32_t kIndexMask = (1u << kIndexBits) - 1, kGenerationMask = (1u << kGenerationBits) - 1;
    static constexpr uint32_t kCapacity = kIndexMask;  // index + 1 must fit in the index bits

    explicit HandlePool(HandleKind kind) : kind_(kind) {}

    bool full() const { return free_.empty() && slots_.size() >= kCapacity; }
    size_t size() const { return slots_.size() - free_.size() - retired_; }
    size_t retired() const { return retired_; }  // slots whose generations are spent

    // Throws Error(Limit) when full(), so a caller can check before changing anything.
    void requireRoom() const {
        if (!full()) return;
        if (retired_ == 0)
            throw Error(ErrorCode::Limit, std::string("too many ") + toString(kind_) + "s (the limit is " +
                                              std::to_string(kCapacity) + ")");
        throw Error(ErrorCode::Limit, std::string("no ") + toString(kind_) + " handles left: " +
                                          std::to_string(size()) + " live, " + std::to_string(retired_) +
                                          " slots retired after " + std::to_string(kGenerationMask) + " uses each (handle_pool.h)");
    }

    uint32_t add(T value) {  // throws as requireRoom()
        requireRoom();
        uint32_t index;
        if (!free_.empty()) {
            index = free_.back();
            free_.pop_back();
        } else {
            index = static_cast<uint32_t>(slots_.size());
            slots_.push_back(Slot{});
        }
        Slot& s = slots_[index];
        s.value = std::move(value);
        s.live = true;
        return idOf(index);
    }

    // Null for 0, another kind, a freed slot or an older generation.
    T* find(uint32_t id) {
        const uint32_t index = indexOf(id);
        return index < slots_.size() ? &slots_[index].value : nullptr;
    }
    const T* find(uint32_t id) const { return const_cast<HandlePool*>(this)->find(id); }

    // As find, but throws InvalidHandle saying why.
    T& get(uint32_t id) {
        if (T* p = find(id)) return *p;
        throw InvalidHandle(whyInvalid(id));
    }
    const T& get(uint32_t id) const { return const_cast<HandlePool*>(this)->get(id); }

    // Frees the slot (the id becomes stale) and returns its value; throws InvalidHandle.
    T take(uint32_t id) {
        get(id);
        const uint32_t index = (id & kIndexMask) - 1;
        Slot& s = slots_[index];
        T value = std::move(s.value);
        s.value = T{};
        s.live = false;
        if (s.generation == kGenerationMask) {
            ++retired_;  // a new generation would repeat an old one: the slot is never used again
        } else {
            ++s.generation;
            free_.push_back(index);
        }
        return value;
    }

    // Frees every live slot whose value satisfies pred; ids of other slots stay valid.
    template <typename Pred>
    void eraseIf(Pred pred) {
        for (uint32_t i = 0; i < slots_.size(); ++i)
            if (slots_[i].live && pred(std::as_const(slots_[i].value))) take(idOf(i));
    }
    void clear() {  // keeps the generations, so ids from before stay stale
        eraseIf([](const T&) { return true; });
    }

    std::string whyInvalid(uint32_t id) const {
        const std::string head = std::string("invalid ") + toString(kind_) + " handle " + std::to_string(id);
        if (id == 0) return head;
        const uint32_t kind = id >> kKindShift;
        if (kind == static_cast<uint32_t>(kind_)) return head + ": stale or unknown (released, destroyed or never made)";
        if (kind >= 1 && kind <= static_cast<uint32_t>(HandleKind::Instance))
            return head + ": a " + toString(static_cast<HandleKind>(kind)) + " handle, not a " + toString(kind_) + " handle";
        return head + ": not a handle";
    }

  private:
    struct Slot {
        T value{};
        uint32_t generation = 1;
        bool live = false;
    };

    uint32_t idOf(uint32_t index) const {
        return (static_cast<uint32_t>(kind_) << kKindShift) | (slots_[index].generation << kIndexBits) | (index + 1);
    }
    // The slot of a live id, else past the end.
    uint32_t indexOf(uint32_t id) const {
        const auto none = static_cast<uint32_t>(slots_.size());
        if ((id >> kKindShift) != static_cast<uint32_t>(kind_) || (id & kIndexMask) == 0) return none;
        const uint32_t index = (id & kIndexMask) - 1;
        if (index >= slots_.size()) return none;
        const Slot& s = slots_[index];
        return s.live && s.generation == ((id >> kIndexBits) & kGenerationMask) ? index : none;
    }

    HandleKind kind_;
    std::vector<Slot> slots_;
    std::vector<uint32_t> free_;
    size_t retired_ = 0;
};

}  // namespace firelook::world
