#include "cli/interrupt.h"

#include <atomic>
#include <csignal>
#include <cstdlib>

namespace firelook::cli {
namespace {

std::atomic<int> g_signal{0};  // the first signal's number
std::atomic<int> g_count{0};   // how many arrived

static_assert(std::atomic<int>::is_always_lock_free, "used from a signal handler");

extern "C" void onSignal(int signal_number) {
    int none = 0;
    g_signal.compare_exchange_strong(none, signal_number);
    // A second signal means "stop now": temporary files may remain then.
    if (g_count.fetch_add(1) >= 1) std::_Exit(128 + g_signal.load());
}

std::string describe(int signal_number) {
    if (signal_number == SIGTERM) return "interrupted by SIGTERM; no output was written";
    return "interrupted by SIGINT; no output was written";
}

}  // namespace

InterruptedError::InterruptedError() : Error(ErrorCode::Cancelled, describe(interruptSignal())) {}

void installInterruptHandler() {
    struct sigaction action {};
    action.sa_handler = onSignal;
    sigemptyset(&action.sa_mask);
    action.sa_flags = SA_RESTART;  // reads and writes go on; the work loops poll the flag
    sigaction(SIGINT, &action, nullptr);
    sigaction(SIGTERM, &action, nullptr);
}

bool interruptRequested() { return g_count.load(std::memory_order_relaxed) > 0; }

int interruptSignal() { return g_signal.load(std::memory_order_relaxed); }

int interruptExitCode() {
    const int signal_number = interruptSignal();
    return 128 + (signal_number == 0 ? SIGINT : signal_number);
}

void throwIfInterrupted() {
    if (interruptRequested()) throw InterruptedError();
}

}  // namespace firelook::cli
