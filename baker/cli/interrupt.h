// Ctrl-C / kill handling for long commands: the first SIGINT or SIGTERM only records which signal
// arrived; the work loops poll it (the path tracers once per pixel) and unwind with
// InterruptedError, so writers delete their temporary files, nothing half-written is left behind
// and an existing output file keeps its bytes. main() then prints one line and exits with
// 128 + the signal number (130 for SIGINT, 143 for SIGTERM), as a shell reports a killed process.
// A second signal exits at once with the same code (temporary files may then remain).
#pragma once

#include <string>

#include "common/error.h"

namespace firelook::cli {

// Code Cancelled; main() tells an interruption by interruptRequested(), not by this type.
struct InterruptedError : Error {
    InterruptedError();
};

void installInterruptHandler();
bool interruptRequested();
// The first signal that arrived (SIGINT or SIGTERM), 0 if none.
int interruptSignal();
// 128 + interruptSignal(): 130 for SIGINT, 143 for SIGTERM (130 if no signal was recorded).
int interruptExitCode();
// Throws InterruptedError if an interrupt arrived.
void throwIfInterrupted();

}  // namespace firelook::cli
