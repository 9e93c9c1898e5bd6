#pragma once
// Cooperative interruption of long runs (SIGINT, SIGTERM): a signal only records itself, and the run
// stops at its next safe point (between frames), after the work in progress is complete on disk.
//
//   InterruptGuard guard;                       // SIGINT, SIGTERM: record the signal from now on
//   for (frame ...) {
//     if (interrupted()) break;                 // a safe point: nothing half-written
//     ... compute and write the frame ...
//   }
//   if (const int sig = interrupted()) return interrupted_exit_code(sig);   // 130, 143
//
// The handler stores the signal number in a lock-free std::atomic<int> and does nothing else (no
// allocation, no I/O): async-signal-safe. It is installed with SA_RESTART, so a write(2) or fsync(2)
// the signal lands in is restarted instead of failing with EINTR (which would turn an interruption into
// an I/O error). Only the first signal is kept and later ones change nothing, so a second Ctrl+C does
// not kill the run half-way through a frame (SIGKILL does: then an AtomicFile temporary can remain,
// never a partial output under its final name).
#include <memory>
#include <string>

namespace spinmotor {

/// Installs the recording handler for SIGINT and SIGTERM and clears the recorded signal; the destructor
/// restores the handlers that were installed before (the recorded signal stays readable). Guards nest;
/// they are meant for a program's main thread, around the part of a run that polls interrupted().
class InterruptGuard {
 public:
  InterruptGuard();
  ~InterruptGuard();
  InterruptGuard(const InterruptGuard&) = delete;
  InterruptGuard& operator=(const InterruptGuard&) = delete;

 private:
  struct Saved;  // the previous sigaction of each signal (keeps <signal.h> out of this header)
  std::unique_ptr<Saved> saved_;
};

/// The first signal recorded since the last InterruptGuard was installed, or 0 if none.
[[nodiscard]] int interrupted() noexcept;

/// The exit status for a run stopped by `signal`: 128 + signal, what a shell reports for a process
/// killed by it (130 for SIGINT, 143 for SIGTERM), so scripts see the same code either way.
[[nodiscard]] constexpr int interrupted_exit_code(int signal) noexcept { return 128 + signal; }

/// "SIGINT", "SIGTERM", or "signal N" (for messages).
[[nodiscard]] std::string signal_name(int signal);

}  // namespace spinmotor
