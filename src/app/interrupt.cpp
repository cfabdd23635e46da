#include "app/interrupt.hpp"

#include <csignal>
#include <cstdio>

namespace rpfem {

namespace {
volatile std::sig_atomic_t g_signal = 0;
extern "C" void record_signal(int signo) { g_signal = signo; }
}  // namespace

void catch_interrupts() {
  struct sigaction sa {};
  sa.sa_handler = record_signal;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
}

int interrupt_signal() { return g_signal; }

const char* signal_name(int signo) {
  if (signo == SIGINT) return "SIGINT";
  if (signo == SIGTERM) return "SIGTERM";
  static char buf[32];
  std::snprintf(buf, sizeof buf, "signal %d", signo);
  return buf;
}

}  // namespace rpfem
