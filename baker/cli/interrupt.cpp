#include "cli/interrupt.h"

#include <atomic>
#include <csignal>
#include <cstdlib>

namespace firelook::cli {
namespace {

std::atomic<int> g_signals{0};

extern "C" void onSignal(int) {
    // A second Ctrl-C means "stop now": temporary files may remain then.
    if (g_signals.fetch_add(1) >= 1) std::_Exit(130);
}

}  // namespace

void installInterruptHandler() {
    std::signal(SIGINT, onSignal);
    std::signal(SIGTERM, onSignal);
}

bool interruptRequested() { return g_signals.load(std::memory_order_relaxed) > 0; }

void throwIfInterrupted() {
    if (interruptRequested()) throw InterruptedError();
}

}  // namespace firelook::cli
