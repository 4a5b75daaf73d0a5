#include "granpack/engine/stop_signals.h"

#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <initializer_list>
#include <thread>

namespace granpack {

namespace {
volatile std::sig_atomic_t g_signal = 0;

extern "C" void on_stop_signal(int signo) {
  g_signal = signo;
  // Ctrl-C twice: the second one is not intercepted.
  if (signo == SIGINT)
    std::signal(SIGINT, SIG_DFL);
}
} // namespace

void install_stop_signal_handlers() {
  struct sigaction sa {};
  sa.sa_handler = on_stop_signal;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = SA_RESTART; // MPI and file calls in progress carry on
  for (int s : {SIGTERM, SIGUSR1, SIGINT})
    sigaction(s, &sa, nullptr);
}

int stop_signal_received() {
  return g_signal;
}

void raise_stop_signal_for_test(int signo) {
  g_signal = signo;
}

void wait_for_stop_signal(double max_seconds) {
  using clock = std::chrono::steady_clock;
  const auto deadline = clock::now() + std::chrono::duration<double>(max_seconds);
  while (g_signal == 0) {
    if (clock::now() > deadline) {
      std::fprintf(stderr, "granpack: GRANPACK_FAULT=hold: no stop signal within %g s; exit 70\n",
                   max_seconds);
      std::fflush(stderr);
      std::_Exit(70);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
}

} // namespace granpack
