// SIGINT, SIGTERM and SIGHUP (what a terminal, a batch scheduler or a closed session sends):
// the first asks the render to stop after its current wave, so that the image so far is
// written and the process exits with 128 + the signal; a second ends the process at once.
#pragma once

#include <string>

namespace pt {

// `doing` replaces what the first signal's message says happens next ("stopping after this
// wave and writing the image"); it must outlive the process's signals (a literal).
void InstallStopSignals(const char* doing = nullptr);

// The first stop signal that arrived, or 0.
int StopSignal();

// "SIGTERM", "SIGINT", "SIGHUP", else "signal N".
std::string SignalName(int signal);

}  // namespace pt
