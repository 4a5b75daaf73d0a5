#pragma once
// SIGTERM, SIGUSR1 and SIGINT ask a run to stop cleanly: the handler only records the
// signal; the MD engine notices it at its next step (all ranks agree through the step's
// all-reduce), writes a checkpoint and the run exits with kExitCheckpointed
// (docs/long-jobs.md). A second SIGINT kills the process as usual (an impatient Ctrl-C).
namespace granpack {

/// Installs the handlers (idempotent). Called by `granpack run`.
void install_stop_signal_handlers();
/// The signal number received since start-up, or 0.
int stop_signal_received();
/// Test hook: behave as if `signo` had been received.
void raise_stop_signal_for_test(int signo);
/// Test hook (GRANPACK_FAULT=hold:N, comm/fault_injection.h): sleeps until a stop signal has
/// been received. After `max_seconds` without one, exits the process with code 70 and a
/// message: a test that holds a run and never signals it must not hang CI.
void wait_for_stop_signal(double max_seconds = 600.0);

} // namespace granpack
