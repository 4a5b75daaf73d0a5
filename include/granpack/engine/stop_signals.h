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

}  // namespace granpack
