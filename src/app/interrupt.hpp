// SIGINT and SIGTERM for `rpfem run`: the handler only records the signal;
// the run stops at its next step boundary (StepObserver::stop_requested),
// writes what it finished and says "interrupted" (exit 128 + the signal).
#pragma once

namespace rpfem {

// Installs the handlers for SIGINT and SIGTERM (idempotent).
void catch_interrupts();
// The signal received since, 0 if none.
int interrupt_signal();
// "SIGINT", "SIGTERM" or "signal N".
const char* signal_name(int signo);

}  // namespace rpfem
