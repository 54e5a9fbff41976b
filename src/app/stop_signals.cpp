#include "src/app/stop_signals.h"

#include <unistd.h>

#include <atomic>
#include <csignal>

namespace pt {
namespace {

constexpr int kStopSignals[] = {SIGINT, SIGTERM, SIGHUP};

std::atomic<int> gStopSignal{0};
constexpr const char* kDefaultDoing = "stopping after this wave and writing the image";
std::atomic<const char*> gDoing{kDefaultDoing};

void WriteStderr(const char* text, size_t size) {
  ssize_t ignored = write(STDERR_FILENO, text, size);
  (void)ignored;
}

// Async-signal-safe: an atomic, write(2), sigaction and raise only.
extern "C" void OnStopSignal(int signal) {
  int expected = 0;
  if (!gStopSignal.compare_exchange_strong(expected, signal)) {
    struct sigaction restore = {};
    restore.sa_handler = SIG_DFL;
    sigemptyset(&restore.sa_mask);
    sigaction(signal, &restore, nullptr);
    raise(signal);
    return;
  }
  if (signal == SIGHUP) {
    // The terminal may be gone: a message to a closed pipe must not kill the final write.
    struct sigaction ignore = {};
    ignore.sa_handler = SIG_IGN;
    sigemptyset(&ignore.sa_mask);
    sigaction(SIGPIPE, &ignore, nullptr);
  }
  const char* name = signal == SIGINT ? "SIGINT" : signal == SIGTERM ? "SIGTERM" : "SIGHUP";
  char message[240] = "\npathtracer: ";
  size_t n = 13;
  for (const char* part : {name, " received: ", gDoing.load(), " (a second signal quits at once)\n"}) {
    for (; *part && n + 1 < sizeof(message); ++part) message[n++] = *part;
  }
  WriteStderr(message, n);
}

}  // namespace

void InstallStopSignals(const char* doing) {
  gDoing = doing ? doing : kDefaultDoing;
  struct sigaction action = {};
  action.sa_handler = OnStopSignal;
  sigemptyset(&action.sa_mask);
  for (int signal : kStopSignals) sigaddset(&action.sa_mask, signal);
  for (int signal : kStopSignals) sigaction(signal, &action, nullptr);
}

int StopSignal() { return gStopSignal.load(std::memory_order_relaxed); }

std::string SignalName(int signal) {
  switch (signal) {
    case SIGINT: return "SIGINT";
    case SIGTERM: return "SIGTERM";
    case SIGHUP: return "SIGHUP";
    default: return "signal " + std::to_string(signal);
  }
}

}  // namespace pt
