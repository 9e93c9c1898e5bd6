#pragma once
// Stop requests (SIGINT, SIGTERM, SIGHUP): cooperative interruption of long runs, and the rule that no
// dependency ever swallows one.
//
// Cooperative interruption: a signal only records itself, and the run stops at its next safe point
// (between frames), after the work in progress is complete on disk.
//
//   InterruptGuard guard;                       // SIGINT, SIGTERM, SIGHUP: record the signal from now on
//   for (frame ...) {
//     if (interrupted()) break;                 // a safe point: nothing half-written
//     ... compute and write the frame ...
//   }
//   if (const int sig = interrupted()) return interrupted_exit_code(sig);   // 129, 130, 143
//
// The handler stores the signal number in a lock-free std::atomic<int> and does nothing else (no
// allocation, no I/O): async-signal-safe. It is installed with SA_RESTART, so a write(2) or fsync(2)
// the signal lands in is restarted instead of failing with EINTR (which would turn an interruption into
// an I/O error). Only the first signal is kept and later ones change nothing, so a second Ctrl+C does
// not kill the run half-way through a frame (SIGKILL does: then an AtomicFile temporary can remain,
// never a partial output under its final name).
//
// Dependencies that trap stop signals. METIS (which CHOLMOD runs to order a matrix or a graph)
// installs its own handler for SIGTERM for the length of each ordering (GKlib's gk_sigtrap, with
// signal(2)); a SIGTERM that lands there is turned into a longjmp out of METIS and an error return
// (CHOLMOD: "could not order"), on a thread whose jump buffer is not set it crashes the process, and
// when METIS puts the previous handler back it does so with System V semantics (one-shot, no
// SA_RESTART). Two mechanisms keep stop requests intact:
//
//   DeferStopSignals defer;     // around the call (linalg does it for every CHOLMOD call that can
//   cholmod_analyze(...);       // order): the stop signals are blocked on this thread, and after it the
//                               // handlers are put back exactly and a pending signal is delivered
//
//   take_stop_signals();        // a program's main(), before any thread starts: every thread blocks the
//                               // stop signals and one thread of their own takes them (sigwait)
//
// A blocked signal goes to another thread of the process that does not block it, and while METIS runs
// its handler is the process's: DeferStopSignals alone is safe only when no other thread can take the
// signal. The project's own threads block them (block_stop_signals_on_this_thread), linalg makes the
// workers of the calling thread's OpenMP team block them too and joins OpenBLAS's idle workers before
// it orders (unless the user set OPENBLAS_NUM_THREADS); a program with threads of its own calls
// take_stop_signals(), as the `spinmotor` tool and the viewer do. No handler of a dependency can take a
// stop signal then, wherever the run is and whichever thread is in METIS.
#include <memory>
#include <string>

namespace spinmotor {

/// Installs the recording handler for SIGINT, SIGTERM and SIGHUP and clears the recorded signal; the
/// destructor restores the handlers that were installed before (the recorded signal stays readable).
/// Guards nest; they are meant for a program's main thread, around the part of a run that polls
/// interrupted(). Under take_stop_signals() the signal thread records the signal instead, for as long
/// as a guard exists.
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
/// killed by it (129 SIGHUP, 130 SIGINT, 143 SIGTERM), so scripts see the same code either way.
[[nodiscard]] constexpr int interrupted_exit_code(int signal) noexcept { return 128 + signal; }

/// "SIGHUP", "SIGINT", "SIGTERM", or "signal N" (for messages).
[[nodiscard]] std::string signal_name(int signal);

/// For its lifetime, SIGINT, SIGTERM and SIGHUP are blocked on the calling thread, and their handlers
/// are saved; the destructor puts the saved handlers back exactly (sigaction: a dependency that
/// replaced one, or put it back with other flags, is undone), then restores the thread's signal mask,
/// so that a stop signal that arrived meanwhile is delivered to the project's handler right then (a
/// handler that only records it, or the one that removes temporaries and ends the process). For calls
/// into code that traps stop signals (METIS). Guards nest, on one thread and across threads: the
/// handlers are saved by the first guard of the process to start and put back by the last to end.
/// Costs a few system calls.
class DeferStopSignals {
 public:
  DeferStopSignals();
  ~DeferStopSignals();
  DeferStopSignals(const DeferStopSignals&) = delete;
  DeferStopSignals& operator=(const DeferStopSignals&) = delete;

  /// Whether the calling thread blocked every stop signal already when the guard started (a nested
  /// guard, or a program under take_stop_signals()).
  [[nodiscard]] bool already_blocked() const noexcept { return already_blocked_; }

 private:
  struct Saved;
  std::unique_ptr<Saved> saved_;
  bool already_blocked_ = false;
};

/// Blocks SIGINT, SIGTERM and SIGHUP on the calling thread for good: for threads that a library starts
/// for its own work, so that only the application's threads take stop signals.
void block_stop_signals_on_this_thread() noexcept;

/// For a program's main(), before it starts any thread: SIGINT, SIGTERM and SIGHUP are blocked on the
/// calling thread, so in every thread started from then on, and one thread of their own waits for them
/// (sigwait) and does what the project's handlers do: while an InterruptGuard exists it records the
/// signal; otherwise it removes the temporaries of the AtomicFiles in flight and ends the process by the
/// signal, as remove_temporary_files_on_signal()'s handler does (atomic_file.hpp; this call installs no
/// handler). A dependency's handler (METIS's) is then never run by a stop signal. A thread started
/// before the call does not block them: OpenBLAS starts its workers when it is loaded, so the program
/// joins them next (linalg's join_idle_blas_workers()). Child processes inherit the blocked mask: start
/// them with the stop signals unblocked (posix_spawnattr_setsigmask). Later calls do nothing.
void take_stop_signals();

/// Whether take_stop_signals() has run in this process.
[[nodiscard]] bool stop_signals_taken() noexcept;

}  // namespace spinmotor
