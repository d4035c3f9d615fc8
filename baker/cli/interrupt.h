// Ctrl-C handling for long commands: the first SIGINT/SIGTERM only sets a flag
// that the work loops poll; they then unwind with InterruptedError, so writers
// delete their temporary files and nothing half-written is left behind.
#pragma once

#include <stdexcept>

namespace firelook::cli {

struct InterruptedError : std::runtime_error {
    InterruptedError() : std::runtime_error("interrupted; no output was written") {}
};

void installInterruptHandler();
bool interruptRequested();
// Throws InterruptedError if an interrupt arrived.
void throwIfInterrupted();

}  // namespace firelook::cli
