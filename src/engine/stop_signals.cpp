#include "granpack/engine/stop_signals.h"

#include <csignal>
#include <initializer_list>

namespace granpack {

namespace {
volatile std::sig_atomic_t g_signal = 0;

extern "C" void on_stop_signal(int signo) {
  g_signal = signo;
  // Ctrl-C twice: the second one is not intercepted.
  if (signo == SIGINT) std::signal(SIGINT, SIG_DFL);
}
}  // namespace

void install_stop_signal_handlers() {
  struct sigaction sa {};
  sa.sa_handler = on_stop_signal;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = SA_RESTART;  // MPI and file calls in progress carry on
  for (int s : {SIGTERM, SIGUSR1, SIGINT}) sigaction(s, &sa, nullptr);
}

int stop_signal_received() { return g_signal; }

void raise_stop_signal_for_test(int signo) { g_signal = signo; }

}  // namespace granpack
